#!/usr/bin/env bash
# Compiles every Shaders/*.comp offline with the preamble terroir::gpu::Program uses at run
# time (#version 430 core, Common.glsl, #line 1). Usage: CheckShaders.sh VALIDATOR SHADERS OUTDIR
set -euo pipefail
validator=$1 shaders=$2 out=$3
mkdir -p "$out"
status=0 count=0
for comp in "$shaders"/*.comp; do
  [ -e "$comp" ] || continue
  name=$(basename "$comp")
  { echo "#version 430 core"; cat "$shaders/Common.glsl" 2>/dev/null || true; echo "#line 1"; cat "$comp"; } > "$out/$name"
  if ! "$validator" -S comp "$out/$name" > "$out/$name.log" 2>&1; then
    echo "FAILED: $name"; cat "$out/$name.log"; status=1
  fi
  count=$((count + 1))
done
echo "checked $count shaders"
exit $status
