#!/usr/bin/env bash
# Submits the whole sweep workflow to Slurm: build, then an array of N shards once the
# build succeeded, then the merge once every shard succeeded.
#   scripts/slurm/submit.sh SWEEP.toml N [OUT] [-- towride sweep options...]
# e.g. scripts/slurm/submit.sh scenes/hitch_variants.toml 10 out/hitch -- --keep-histories
# With TOWRIDE_BIN set to a built binary nothing is built: the array runs that binary.
# The build job asks for the CPUs of the cluster's smallest node (sinfo), or
# TOWRIDE_BUILD_CPUS.
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
if [ -n "${TOWRIDE_BIN:-}" ]; then
    case "$TOWRIDE_BIN" in /*) ;; *) TOWRIDE_BIN="$PWD/$TOWRIDE_BIN" ;; esac
    if [ ! -x "$TOWRIDE_BIN" ]; then
        echo "error: TOWRIDE_BIN=$TOWRIDE_BIN is not an executable file" >&2
        exit 2
    fi
    export TOWRIDE_BIN
    vars="$vars,TOWRIDE_BIN"
    build="none (TOWRIDE_BIN given)"
    after=()
else
    cpus="${TOWRIDE_BUILD_CPUS:-$( (sinfo -h -o %c 2>/dev/null || true) | tr -d '+' | sort -n | head -1)}"
    build=$(sbatch --parsable --export="$vars" --cpus-per-task="${cpus:-1}" \
        "$here/build.sbatch")
    build="${build%%;*}"
    after=(--dependency="afterok:$build")
fi
array=$(sbatch --parsable --export="$vars" "${after[@]}" \
    --array="0-$((n - 1))" "$here/shard.sbatch")
merge=$(sbatch --parsable --export="$vars" --dependency="afterok:${array%%;*}" \
    "$here/merge.sbatch")
echo "build $build, shards ${array%%;*} (array 0-$((n - 1))), merge ${merge%%;*}"
echo "results: $out/summary.csv and $out/report.html once job ${merge%%;*} ends"
