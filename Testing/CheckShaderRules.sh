#!/usr/bin/env bash
# Rules of Documentation/Shaders.md that a compiler cannot check, over every Shaders/*.comp:
#  - work-group and invocation ids through Common.glsl's TERROIR_* macros (the stress modes
#    split dispatches), never gl_GlobalInvocationID, gl_WorkGroupID or gl_NumWorkGroups;
#  - no local arrays of double or dvecN (NVIDIA's compiler, driver 580.159.04, returned other
#    values than those stored in them; buffers and shared memory are not local arrays).
# Usage: CheckShaderRules.sh SHADERS_DIR
set -euo pipefail
dir=$1
status=0
for comp in "$dir"/*.comp; do
  name=$(basename "$comp")
  # Comments are not code.
  code=$(sed -e 's|//.*$||' "$comp")
  if grep -nE '\bgl_(GlobalInvocationID|WorkGroupID|NumWorkGroups)\b' <<< "$code"; then
    echo "FAILED: $name reads gl_* ids: use TERROIR_GLOBAL_ID, TERROIR_WORKGROUP_ID, TERROIR_NUM_WORKGROUPS"
    status=1
  fi
  if grep -nE '\b(double|dvec[234])\s+[A-Za-z_][A-Za-z0-9_]*\s*\[' <<< "$code" |
    grep -vE '\bbuffer\b|\bshared\b'; then
    echo "FAILED: $name declares a local array of doubles"
    status=1
  fi
done
echo "checked $(ls "$dir"/*.comp | wc -l) shaders"
exit $status
