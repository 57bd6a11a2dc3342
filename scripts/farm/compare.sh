#!/usr/bin/env bash
# One pass over every frame against the farm recipe's two tasks side by side
# (scripts/farm/local.sh), each on a fresh copy of one simulated cache (its surfaces,
# previews and stage removed), alternated REPEATS times; then the two caches compared
# file by file (docs/farm.md, "Measured here").
#
#   scripts/farm/compare.sh CACHE BINARY METHOD [REPEATS]
set -euo pipefail
src="$1"; bin="$2"; method="$3"; repeats="${4:-3}"
export PERIFRAC="$bin"
here="$(cd "$(dirname "$0")" && pwd)"
strip() { rm -rf "$1"/surface "$1"/vdb "$1"/preview "$1"/usd "$1"/cache.usd "$1"/.manifest.lock; }
for r in $(seq "$repeats"); do
  for way in one farm; do
    rm -rf /tmp/fb-$way; cp -r "$src" /tmp/fb-$way; strip /tmp/fb-$way
    start=$(date +%s.%N)
    if [ $way = one ]; then
      "$bin" surface /tmp/fb-one --method "$method" --quiet
      "$bin" render /tmp/fb-one --movie --quiet
      "$bin" export usd /tmp/fb-one --quiet
    else
      "$here/local.sh" /tmp/fb-farm 2 "$method" > /dev/null
    fi
    end=$(date +%s.%N)
    echo "repeat $r $way: $(python3 -c "print(f'{$end-$start:.1f}')") s"
  done
done
diff -rq /tmp/fb-one /tmp/fb-farm | grep -v manifest.lock || true
