#!/usr/bin/env bash
# Writes the synthetic example set: the 72-run measurement plan (3 obstacles x 6 speeds x
# 4 trailer loads) simulated by towride's default simulator and passed through the sensor
# model of docs/validation.md. Every file is labelled synthetic and names the simulator.
# The scenes per obstacle default to scenes/{bump_25mm,bump_50mm,default}.toml; replace one with
#   ./measurements/make_synthetic.sh --plan-scene bump_25mm=scenes/my_scene.toml
set -euo pipefail
cd "$(dirname "$0")/.."
out=measurements/synthetic
rm -rf "$out"
cargo run --release -- validate synth --plan --rate-hz 500 --out "$out" "$@"
cargo run --release -- validate "$out" --no-plots --out out/validate-synthetic
