#!/usr/bin/env bash
# Writes the synthetic example set: the 72-run measurement plan (3 obstacles x 6 speeds x
# 4 trailer loads) simulated by towride's default simulator and passed through the sensor
# model of docs/validation.md. Every file is labelled synthetic and names the simulator.
# With the vehicle model as default simulator, give its scenes per obstacle:
#   ./measurements/make_synthetic.sh --plan-scene bump_25mm=scenes/... --plan-scene ...
set -euo pipefail
cd "$(dirname "$0")/.."
out=measurements/synthetic
rm -rf "$out"
cargo run --release -- validate synth --plan --out "$out" "$@"
cargo run --release -- validate "$out" --no-plots --out out/validate-synthetic
