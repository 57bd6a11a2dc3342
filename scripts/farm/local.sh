#!/usr/bin/env bash
# The farm recipe on one machine, for trying it without a farm (docs/farm.md): the
# tasks of each array started side by side, as a farm would run them, then the join.
#
#   scripts/farm/local.sh OUT [TASKS] [METHOD]
#
# METHOD: the surface method (vdb, the default, or embedded or sheet).
set -euo pipefail
out="$1"; tasks="${2:-2}"; method="${3:-vdb}"
here="$(cd "$(dirname "$0")" && pwd)"
perifrac="${PERIFRAC:-perifrac}"
for stage in surface render; do
  pids=()
  flags=(--quiet)
  [ "$stage" = surface ] && flags+=(--method "$method")
  for ((t = 0; t < tasks; t++)); do
    FARM_TASK=$t FARM_TASKS=$tasks "$here/task.sh" "$stage" "$out" "${flags[@]}" &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid"; done
done
"$perifrac" render "$out" --join --movie --quiet
"$perifrac" export usd "$out" --quiet
"$perifrac" verify "$out"
