#!/usr/bin/env bash
# Submits the whole sweep workflow to Slurm: build, then an array of N shards once the
# build succeeded, then the merge once every shard succeeded.
#   scripts/slurm/submit.sh SWEEP.toml N [OUT] [-- towride sweep options...]
# e.g. scripts/slurm/submit.sh scenes/hitch_variants.toml 10 out/hitch -- --keep-histories
set -euo pipefail
if [ $# -lt 2 ]; then
    sed -n '2,5p' "$0" >&2
    exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
sweep="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
n="$2"
out="${3:-$repo/out/sweep}"
shift $(($# < 3 ? $# : 3))
[ "${1:-}" = "--" ] && shift
case "$out" in /*) ;; *) out="$PWD/$out" ;; esac
mkdir -p "$out"
export TOWRIDE_REPO="$repo" TOWRIDE_SWEEP="$sweep" TOWRIDE_SHARDS="$n" TOWRIDE_OUT="$out"
export TOWRIDE_SWEEP_ARGS="$*"
vars="ALL,TOWRIDE_REPO,TOWRIDE_SWEEP,TOWRIDE_SHARDS,TOWRIDE_OUT,TOWRIDE_SWEEP_ARGS"
cd "$out"
build=$(sbatch --parsable --export="$vars" "$here/build.sbatch")
array=$(sbatch --parsable --export="$vars" --dependency="afterok:${build%%;*}" \
    --array="0-$((n - 1))" "$here/shard.sbatch")
merge=$(sbatch --parsable --export="$vars" --dependency="afterok:${array%%;*}" \
    "$here/merge.sbatch")
echo "build ${build%%;*}, shards ${array%%;*} (array 0-$((n - 1))), merge ${merge%%;*}"
echo "results: $out/summary.csv and $out/report.html once job ${merge%%;*} ends"
