# Settings shared by the Slurm steps (sourced by build.sbatch, shard.sbatch, merge.sbatch).
# Every value can be set in the environment first; submit.sh passes them with --export.
#   TOWRIDE_REPO        the repository (default: two folders above this file)
#   TOWRIDE_BIN         the binary the array runs (default: REPO/target/release/towride)
#   TOWRIDE_SWEEP       the sweep file (required by shard and merge)
#   TOWRIDE_SHARDS      N, the number of array tasks (required by shard and merge)
#   TOWRIDE_OUT         the sweep's output folder (default: REPO/out/sweep)
#   TOWRIDE_SWEEP_ARGS  more `towride sweep` options, e.g. "--keep-histories"
#   TOWRIDE_JOBS        cases run at once in a task (default: SLURM_CPUS_PER_TASK, else 1)
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
: "${TOWRIDE_REPO:=$(cd "$here/../.." && pwd)}"
: "${TOWRIDE_BIN:=$TOWRIDE_REPO/target/release/towride}"
: "${TOWRIDE_OUT:=$TOWRIDE_REPO/out/sweep}"
: "${TOWRIDE_SWEEP_ARGS:=}"
: "${TOWRIDE_JOBS:=${SLURM_CPUS_PER_TASK:-1}}"
export TOWRIDE_REPO TOWRIDE_BIN TOWRIDE_OUT TOWRIDE_SWEEP_ARGS TOWRIDE_JOBS

need() {
    if [ -z "${!1:-}" ]; then
        echo "error: $1 is not set (see scripts/slurm/README.md)" >&2
        exit 2
    fi
}
