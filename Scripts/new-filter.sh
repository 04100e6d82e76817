#!/usr/bin/env bash
# Writes the skeleton of a new Terroir filter and registers it everywhere a filter is listed
# (Documentation/Architecture.md, "Adding a filter").
#
#   Scripts/new-filter.sh NAME MODULE [--root DIR]
#
# NAME: the class is vtkTerroirNAME (CamelCase, e.g. SnowCover); its command is `terroir name`
# (lower case). MODULE: Terrain, Hydrology or Clustering. --root: the source tree to write into
# (default: this script's checkout).
#
# Writes (from Scripts/FilterTemplate/*.in):
#   Filters/MODULE/Core/NAME.{h,cxx}          plain C++ core (no VTK, no GL)
#   Filters/MODULE/vtkTerroirNAME.{h,cxx}     the VTK filter: CPU and GPU paths
#   Shaders/NAME.comp                         the GPU kernel
#   Testing/Unit/TestNAME.cxx                 core tests
#   Testing/Pipeline/TestTerroirNAME.cxx      the filter's VTK contract
#   Testing/GPU/TestNAMEGPU.cxx               GPU against CPU
#   Applications/Commands/NAME{,Options}.cxx  `terroir name IN OUT [--scale F]`
#   Documentation/Filters/vtkTerroirNAME.md   the filter's page
#   Testing/Fuzz/corpus/CommandLine/name      a seed of the command-line fuzzer
# and adds one line or entry at each `new-filter.sh:` marker: the module's classes, shaders and
# core sources, the command's entry, options factory, registry entry and CommandLine field, a
# `terroir bench` stage, the two determinism lists, the shader table (Shaders/README.md) and the
# command table (CLI.md).
# The skeleton computes Scale x elevation on both paths; it builds, and its placeholder tests
# fail (ADD_FAILURE) until they are replaced by real ones: grep -rn 'TODO(new-filter)'.
# Nothing is written when a check fails (a bad name, a file or class that exists, a marker
# missing).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
templates="$here/FilterTemplate"
root="$(cd "$here/.." && pwd)"

fail() {
  echo "new-filter.sh: $*" >&2
  exit 1
}

args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --root)
      [[ $# -ge 2 ]] || fail "--root needs a folder"
      root="$(cd "$2" && pwd)" || fail "$2: no such folder"
      shift 2
      ;;
    -h | --help)
      sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    -*) fail "unknown option $1 (see --help)" ;;
    *)
      args+=("$1")
      shift
      ;;
  esac
done
[[ ${#args[@]} -eq 2 ]] || fail "usage: new-filter.sh NAME MODULE [--root DIR] (see --help)"
Name="${args[0]}"
Module="${args[1]}"
[[ "$Name" =~ ^[A-Z][A-Za-z0-9]{1,40}$ ]] ||
  fail "NAME '$Name' must be CamelCase letters and digits, starting with a capital (e.g. SnowCover)"
case "$Module" in
  Terrain) ns=terrain ;;
  Hydrology) ns=hydrology ;;
  Clustering) ns=clustering ;;
  *) fail "MODULE '$Module' must be Terrain, Hydrology or Clustering" ;;
esac
name="$(tr '[:upper:]' '[:lower:]' <<< "$Name")"
UPPER="$(tr '[:lower:]' '[:upper:]' <<< "$Name")"
MODULE="$(tr '[:lower:]' '[:upper:]' <<< "$Module")"

# ---- what is written and where ----------------------------------------------------------------
declare -A outputs=(
  [Core.h.in]="Filters/$Module/Core/$Name.h"
  [Core.cxx.in]="Filters/$Module/Core/$Name.cxx"
  [Filter.h.in]="Filters/$Module/vtkTerroir$Name.h"
  [Filter.cxx.in]="Filters/$Module/vtkTerroir$Name.cxx"
  [Kernel.comp.in]="Shaders/$Name.comp"
  [UnitTest.cxx.in]="Testing/Unit/Test$Name.cxx"
  [PipelineTest.cxx.in]="Testing/Pipeline/TestTerroir$Name.cxx"
  [GPUTest.cxx.in]="Testing/GPU/Test${Name}GPU.cxx"
  [Command.cxx.in]="Applications/Commands/$Name.cxx"
  [CommandOptions.cxx.in]="Applications/Commands/${Name}Options.cxx"
  [Doc.md.in]="Documentation/Filters/vtkTerroir$Name.md"
)
corpus="Testing/Fuzz/corpus/CommandLine/$name"

# Registrations: FILE|MARKER|TEXT (TEXT is inserted as lines just above the marker's line).
registrations=(
  "Filters/$Module/CMakeLists.txt|# new-filter.sh: classes|    vtkTerroir$Name"
  "Filters/$Module/CMakeLists.txt|# new-filter.sh: shaders|  $Name"
  "Filters/$Module/Core/CMakeLists.txt|# new-filter.sh: sources|    $Name.cxx"
  "Filters/$Module/Core/CMakeLists.txt|# new-filter.sh: headers|  $Name.h"
  "Applications/TerroirCommandLine.h|// new-filter.sh: options|  double ${Name}Scale = 1.0; ///< $name --scale"
  "Applications/TerroirCommandLine.cxx|// new-filter.sh: commands|    { \"$name\", \"TODO(new-filter): one line for --help\", Make${Name}Options },"
  "Applications/Commands/TerroirCommandOptions.h|// new-filter.sh: options factories|std::unique_ptr<CommandOptions> Make${Name}Options(); // ${Name}Options.cxx"
  "Applications/Commands/TerroirCommands.h|// new-filter.sh: commands|int Command$Name(const CommandLine& c); // $Name.cxx"
  "Applications/Commands/TerroirCommands.cxx|// new-filter.sh: commands|    { \"$name\", Command$Name },"
  "Applications/TerroirCommandLine.cxx|// new-filter.sh: stages|    \"$name\","
  "Applications/TerroirBenchStages.cxx|// new-filter.sh: includes|#include \"vtkTerroir$Name.h\""
  "Applications/TerroirBenchStages.cxx|// new-filter.sh: stages|    { \"$name\",
      false,
      [](BenchRun& run) { BenchFilter(run, vtkSmartPointer<vtkTerroir$Name>::New(), \"$name\"); } },"
  "Testing/Pipeline/TestDeterminism.cxx|// new-filter.sh: includes|#include \"vtkTerroir$Name.h\""
  "Testing/Pipeline/TestDeterminism.cxx|// new-filter.sh: cases|    { \"vtkTerroir$Name\",
      []
      {
        vtkNew<vtkTerroir$Name> f;
        f->SetBackendToCPU();
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },"
  "Testing/GPU/TestDeterminismGPU.cxx|// new-filter.sh: includes|#include \"vtkTerroir$Name.h\""
  "Testing/GPU/TestDeterminismGPU.cxx|// new-filter.sh: cases|    { \"vtkTerroir$Name\",
      { [] { return vtkSmartPointer<vtkTerroir$Name>::New(); }, { { \"$Name\", 0.0 } } } },"
  "Shaders/README.md|<!-- new-filter.sh: shaders -->|| \`$Name.comp\` | 0 \`float elevation[]\` (ro); 1 \`uint validMask[(n+3)/4]\` (ro, \`${UPPER}_MASK\`); 2 \`float result[n]\` (wo) | \`uint uCount; float uScale\`; define \`${UPPER}_MASK\` | 256; \`gx × gy\` groups covering \`n\` cells | \`terroir::$ns::${Name}Rows\` |"
  "Documentation/CLI.md|<!-- new-filter.sh: commands -->|| \`terroir $name IN OUT [--scale F]\` | TODO(new-filter): what it writes (\`vtkTerroir$Name\`, [Filters/vtkTerroir$Name.md](Filters/vtkTerroir$Name.md)). |"
)

# ---- checks first: nothing is written unless all pass -------------------------------------------
[[ -d "$root/Filters/$Module" ]] || fail "$root is not a Terroir source tree (no Filters/$Module)"
for t in "${!outputs[@]}"; do
  [[ -f "$templates/$t" ]] || fail "$templates/$t is missing"
  [[ ! -e "$root/${outputs[$t]}" ]] || fail "${outputs[$t]} exists already"
done
[[ ! -e "$root/$corpus" ]] || fail "$corpus exists already"
if grep -rqw --include='*.h' "vtkTerroir$Name" "$root/Filters" "$root/IO" "$root/Rendering" 2>/dev/null; then
  fail "a class vtkTerroir$Name exists already"
fi
if grep -q "{ \"$name\"," "$root/Applications/TerroirCommandLine.cxx"; then
  fail "a command '$name' exists already"
fi
for r in "${registrations[@]}"; do
  file="${r%%|*}"
  rest="${r#*|}"
  marker="${rest%%|*}"
  [[ -f "$root/$file" ]] || fail "$file is missing"
  [[ $(grep -cF -- "$marker" "$root/$file") -eq 1 ]] ||
    fail "$file must hold the line '$marker' once (where the new entry goes)"
done

# ---- write --------------------------------------------------------------------------------------
written=()
cleanup() { # on any failure from here on, take back what was written
  if [[ $? -ne 0 ]]; then
    for f in "${written[@]}"; do rm -f "$root/$f"; done
    for f in "${edited[@]}"; do [[ -f "$root/$f.new-filter.orig" ]] && mv "$root/$f.new-filter.orig" "$root/$f"; done
    echo "new-filter.sh: failed; nothing was kept" >&2
  fi
  for f in "${edited[@]}"; do rm -f "$root/$f.new-filter.orig"; done
}
edited=()
trap cleanup EXIT

for t in "${!outputs[@]}"; do
  out="${outputs[$t]}"
  sed -e "s/@Name@/$Name/g" -e "s/@name@/$name/g" -e "s/@UPPER@/$UPPER/g" \
    -e "s/@Module@/$Module/g" -e "s/@MODULE@/$MODULE/g" -e "s/@ns@/$ns/g" \
    "$templates/$t" > "$root/$out"
  written+=("$out")
done
printf '%s\0in.tif\0out.tif\0--scale\0%s' "$name" "2.5" > "$root/$corpus"
written+=("$corpus")

for r in "${registrations[@]}"; do
  file="${r%%|*}"
  rest="${r#*|}"
  marker="${rest%%|*}"
  text="${rest#*|}"
  if [[ ! -f "$root/$file.new-filter.orig" ]]; then
    cp "$root/$file" "$root/$file.new-filter.orig"
    edited+=("$file")
  fi
  MARKER="$marker" TEXT="$text" awk '
    index($0, ENVIRON["MARKER"]) { print ENVIRON["TEXT"] }
    { print }' "$root/$file" > "$root/$file.new-filter.tmp"
  mv "$root/$file.new-filter.tmp" "$root/$file"
done

echo "new-filter.sh: vtkTerroir$Name in Terroir::Filters$Module, command 'terroir $name'"
echo "written:"
printf '  %s\n' "${written[@]}" | sort
echo "registered in:"
printf '  %s\n' "${edited[@]}"
echo "next: fill in every TODO(new-filter) (grep -rn 'TODO(new-filter)' .), build, and make the"
echo "placeholder tests pass with real ones (Documentation/Architecture.md, 'Adding a filter')."
