#!/usr/bin/env bash
# One array task of a perifrac stage on a farm (docs/farm.md): frames of the cache OUT
# split into TASKS contiguous chunks, this task doing chunk TASK (from 0).
#
#   scripts/farm/task.sh surface|render OUT [extra perifrac flags…]
#
# TASK and TASKS come from Slurm (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT, the
# array starting at 0) or, elsewhere, from FARM_TASK and FARM_TASKS. Threads:
# SLURM_CPUS_PER_TASK, else FARM_THREADS, else 1. PERIFRAC names the binary (default:
# perifrac on the PATH).
set -euo pipefail
stage="$1"; out="$2"; shift 2
task="${SLURM_ARRAY_TASK_ID:-${FARM_TASK:?set FARM_TASK (from 0) or run under a Slurm array}}"
tasks="${SLURM_ARRAY_TASK_COUNT:-${FARM_TASKS:?set FARM_TASKS or run under a Slurm array}}"
threads="${SLURM_CPUS_PER_TASK:-${FARM_THREADS:-1}}"
perifrac="${PERIFRAC:-perifrac}"
frames=$(find "$out/particles" -maxdepth 1 -name '[0-9][0-9][0-9][0-9].ply' | wc -l)
if [ "$frames" -eq 0 ]; then
  echo "farm task: $out/particles holds no frames; simulate first (perifrac run)" >&2
  exit 2
fi
chunk=$(( (frames + tasks - 1) / tasks ))
first=$(( task * chunk + 1 ))
last=$(( first + chunk - 1 ))
if [ "$first" -gt "$frames" ]; then
  echo "farm task $task of $tasks: nothing to do ($frames frames in chunks of $chunk)"
  exit 0
fi
# perifrac cuts a last chunk that runs past the end.
exec "$perifrac" "$stage" "$out" --frames "$first..$last" --threads "$threads" "$@"
