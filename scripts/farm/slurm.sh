#!/usr/bin/env bash
# Submits a simulated cache's surfaces and previews to Slurm as two array jobs and a
# join (docs/farm.md):
#
#   scripts/farm/slurm.sh OUT [TASKS] [CPUS] [METHOD]
#
# the surface array (TASKS tasks of CPUS cores), the render array after it (previews
# read the surfaces), then one job that joins the previews into the contact sheet and
# movies and writes cache.usd. METHOD is the surface method (vdb, embedded, sheet; the
# embedded and sheet methods' animated.glb needs a pass over every frame, which a
# job of its own can run: perifrac surface OUT --method embedded). OUT must be on
# storage every node sees.
set -euo pipefail
out="$1"; tasks="${2:-8}"; cpus="${3:-4}"; method="${4:-vdb}"
here="$(cd "$(dirname "$0")" && pwd)"
array=(--parsable --array="0-$((tasks - 1))" --cpus-per-task="$cpus")
surface=$(sbatch "${array[@]}" --job-name=perifrac-surface \
  --wrap "$here/task.sh surface '$out' --method $method")
render=$(sbatch "${array[@]}" --job-name=perifrac-render --dependency="afterok:$surface" \
  --wrap "$here/task.sh render '$out'")
join=$(sbatch --parsable --job-name=perifrac-join --dependency="afterok:$render" \
  --wrap "perifrac render '$out' --join --movie && perifrac export usd '$out' && perifrac verify '$out'")
echo "submitted: surface $surface, render $render, join $join"
