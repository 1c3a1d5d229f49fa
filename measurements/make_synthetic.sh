#!/usr/bin/env bash
# Writes the synthetic example set: the 72-run measurement plan (3 obstacles x 6 speeds x
# 4 trailer loads) simulated by towride's default simulator and passed through the sensor
# model of docs/validation.md. Every file is labelled synthetic and names the simulator.
# The plan is scenes/measurement_plan.toml (its obstacles name their scenes); another plan:
#   PLAN=my_plan.toml ./measurements/make_synthetic.sh
set -euo pipefail
cd "$(dirname "$0")/.."
out=measurements/synthetic
rm -rf "$out"
cargo run --release -- validate synth --plan "${PLAN:-scenes/measurement_plan.toml}" --rate-hz 500 --out "$out" "$@"
cargo run --release -- validate "$out" --no-plots --out out/validate-synthetic
