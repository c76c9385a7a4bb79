#!/usr/bin/env bash
# The layers depend one way (docs/architecture.md): a file may include headers of its own layer
# and of the layers below it, never above. Prints every include that runs back up.
set -euo pipefail
cd "$(dirname "$0")/.."
layers=(math sampling guiding scene integrators film render cli)
rank() { for i in "${!layers[@]}"; do [ "${layers[$i]}" = "$1" ] && echo "$i" && return; done; echo -1; }
bad=0
while IFS= read -r line; do
  file=${line%%:*}
  target=$(sed -E 's/.*#include "brume\/([a-z_]+)\/.*/\1/' <<<"$line")
  from=$(sed -E 's#^(src|include/brume)/([a-z_]+)/.*#\2#' <<<"$file")
  rf=$(rank "$from"); rt=$(rank "$target")
  if [ "$rf" -lt 0 ] || [ "$rt" -lt 0 ]; then echo "unknown layer: $line"; bad=1; continue; fi
  if [ "$rt" -gt "$rf" ]; then echo "up the layers ($from -> $target): $line"; bad=1; fi
done < <(grep -rn '#include "brume/' src include)
exit $bad
