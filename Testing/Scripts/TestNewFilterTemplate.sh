#!/usr/bin/env bash
# Scripts/new-filter.sh on a copy of the source tree (Documentation/Architecture.md, "Adding a
# filter"): bad requests are refused with nothing written; a good one writes every skeleton file
# and registers the filter at every marker; the tree then configures with CMake, every generated
# or edited C++ file compiles (-fsyntax-only, with the flags the build uses for its sibling), the
# shader keeps the kernel rules, and each test file holds a failing placeholder.
#
#   TestNewFilterTemplate.sh SOURCE_DIR BUILD_DIR SCRATCH_DIR
set -euo pipefail
src=$1
build=$2
scratch=$3
tree="$scratch/tree"
rm -rf "$scratch"
mkdir -p "$tree"
for d in Applications CMake Common Compute Documentation Examples Filters IO Rendering Scripts \
  Shaders Testing; do
  cp -r "$src/$d" "$tree/$d"
done
cp "$src/CMakeLists.txt" "$tree/"
rm -rf "$tree/Testing/Temporary"
script="$tree/Scripts/new-filter.sh"
fails=0
check() { # MESSAGE COMMAND...: runs COMMAND, reports a failure with MESSAGE
  local message=$1
  shift
  if ! "$@"; then
    echo "FAILED: $message"
    fails=$((fails + 1))
  fi
}
snapshot() { (cd "$tree" && find . -type f -not -path './build/*' | sort | xargs md5sum); }
refused() { # ARGS...: new-filter.sh must exit 1 with one line on stderr and change nothing
  local before after err
  before=$(snapshot)
  if err=$(bash "$script" "$@" --root "$tree" 2>&1 >/dev/null); then
    echo "FAILED: new-filter.sh $* was accepted"
    fails=$((fails + 1))
    return
  fi
  after=$(snapshot)
  [[ "$before" == "$after" ]] || { echo "FAILED: new-filter.sh $* changed the tree"; fails=$((fails + 1)); }
  [[ $(wc -l <<< "$err") -eq 1 && "$err" == new-filter.sh:* ]] ||
    { echo "FAILED: new-filter.sh $*: not one line: $err"; fails=$((fails + 1)); }
  echo "refused as expected: $*: $err"
}

# ---- refusals -----------------------------------------------------------------------------------
refused aridity Terrain         # not CamelCase
refused Aridity Geology         # no such module
refused Slope Terrain           # the class exists
refused Aridity                 # missing argument
cp "$tree/Testing/GPU/TestDeterminismGPU.cxx" "$scratch/saved.cxx"
sed -i '/new-filter.sh: cases/d' "$tree/Testing/GPU/TestDeterminismGPU.cxx"
refused Aridity Terrain         # a marker is missing
cp "$scratch/saved.cxx" "$tree/Testing/GPU/TestDeterminismGPU.cxx"

# ---- a filter -----------------------------------------------------------------------------------
bash "$script" Aridity Terrain --root "$tree"
written=(Filters/Terrain/Core/Aridity.h Filters/Terrain/Core/Aridity.cxx
  Filters/Terrain/vtkTerroirAridity.h Filters/Terrain/vtkTerroirAridity.cxx Shaders/Aridity.comp
  Testing/Unit/TestAridity.cxx Testing/Pipeline/TestTerroirAridity.cxx
  Testing/GPU/TestAridityGPU.cxx Applications/Commands/Aridity.cxx
  Applications/Commands/AridityOptions.cxx Documentation/Filters/vtkTerroirAridity.md
  Testing/Fuzz/corpus/CommandLine/aridity)
for f in "${written[@]}"; do
  check "$f written" test -s "$tree/$f"
  check "$f has no template placeholder left" bash -c "! grep -q '@[A-Za-z]*@' '$tree/$f'"
done
registered=(
  "Filters/Terrain/CMakeLists.txt:vtkTerroirAridity" "Filters/Terrain/CMakeLists.txt:  Aridity"
  "Filters/Terrain/Core/CMakeLists.txt:Aridity.cxx" "Filters/Terrain/Core/CMakeLists.txt:Aridity.h"
  "Applications/TerroirCommandLine.h:AridityScale" "Applications/TerroirCommandLine.cxx:MakeAridityOptions"
  "Applications/Commands/TerroirCommandOptions.h:MakeAridityOptions"
  "Applications/Commands/TerroirCommands.h:CommandAridity"
  "Applications/Commands/TerroirCommands.cxx:CommandAridity"
  "Testing/Pipeline/TestDeterminism.cxx:vtkNew<vtkTerroirAridity>"
  "Testing/GPU/TestDeterminismGPU.cxx:vtkSmartPointer<vtkTerroirAridity>"
  "Applications/TerroirBenchStages.cxx:vtkSmartPointer<vtkTerroirAridity>"
  "Applications/TerroirCommandLine.cxx:    \"aridity\","
  "Shaders/README.md:Aridity.comp" "Documentation/CLI.md:terroir aridity")
for r in "${registered[@]}"; do
  check "${r%%:*} registers ${r#*:}" grep -qF -- "${r#*:}" "$tree/${r%%:*}"
done
check "no backup or temporary file left" bash -c "! find '$tree' -name '*.new-filter.*' | grep -q ."
refused Aridity Terrain         # now it exists
for t in Testing/Unit/TestAridity.cxx Testing/Pipeline/TestTerroirAridity.cxx \
  Testing/GPU/TestAridityGPU.cxx; do
  check "$t holds a failing placeholder" grep -q 'ADD_FAILURE() << "placeholder' "$tree/$t"
done

# ---- it builds ----------------------------------------------------------------------------------
if ! cmake -S "$tree" -B "$tree/build" -DTERROIR_WRAP_PYTHON=OFF \
  -DPython3_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release >"$scratch/configure.log" 2>&1; then
  tail -20 "$scratch/configure.log"
  echo "FAILED: the tree configures"
  fails=$((fails + 1))
fi
check "the shader keeps the kernel rules" bash "$tree/Testing/CheckShaderRules.sh" "$tree/Shaders"
if command -v glslangValidator >/dev/null; then
  check "the shader compiles" bash "$tree/Testing/CheckShaders.sh" "$(command -v glslangValidator)" \
    "$tree/Shaders" "$scratch/shaders"
fi
mkdir -p "$scratch/stub"
echo 'extern const char* vtkTerroirAridityCS;' > "$scratch/stub/vtkTerroirAridityCS.h"
# Each generated or edited file, compiled with the flags of its sibling in the real build.
pairs=(
  Filters/Terrain/Core/Aridity.cxx=Filters/Terrain/Core/TemperatureLapseRate.cxx
  Filters/Terrain/vtkTerroirAridity.cxx=Filters/Terrain/vtkTerroirTemperature.cxx
  Testing/Unit/TestAridity.cxx=Testing/Unit/TestTemperatureLapseRate.cxx
  Testing/Pipeline/TestTerroirAridity.cxx=Testing/Pipeline/TestTerroirTemperature.cxx
  Testing/GPU/TestAridityGPU.cxx=Testing/GPU/TestTemperatureGPU.cxx
  Applications/Commands/Aridity.cxx=Applications/Commands/Temperature.cxx
  Applications/Commands/AridityOptions.cxx=Applications/Commands/TemperatureOptions.cxx
  Applications/TerroirCommandLine.cxx=Applications/TerroirCommandLine.cxx
  Applications/Commands/TerroirCommands.cxx=Applications/Commands/TerroirCommands.cxx
  Applications/TerroirBenchStages.cxx=Applications/TerroirBenchStages.cxx
  Testing/Pipeline/TestDeterminism.cxx=Testing/Pipeline/TestDeterminism.cxx
  Testing/GPU/TestDeterminismGPU.cxx=Testing/GPU/TestDeterminismGPU.cxx)
for p in "${pairs[@]}"; do
  new=${p%%=*}
  sibling=${p#*=}
  cmd=$(/usr/bin/python3 - "$build/compile_commands.json" "$src" "$tree" "$sibling" "$new" \
    "$scratch/stub" <<'PY'
import json, re, shlex, sys
db, src, tree, sibling, new, stub = sys.argv[1:]
for e in json.load(open(db)):
    if e["file"] == src + "/" + sibling:
        args = shlex.split(e["command"]) if "command" in e else e["arguments"]
        out = []
        skip = False
        for a in args:
            if skip:
                skip = False
                continue
            if a in ("-o", "-c"):
                skip = True
                continue
            if a == src + "/" + sibling:
                continue
            # Source folders of the copy instead of the original's (the build folder stays).
            a = re.sub(re.escape(src) + r"/(Applications|Common|Compute|Filters|IO|Rendering|Testing)(?=/|$)",
                       tree + r"/\1", a)
            out.append(a)
        out += ["-I" + stub, "-fsyntax-only", tree + "/" + new]
        print(" ".join(shlex.quote(a) for a in out))
        break
PY
)
  if [[ -z "$cmd" ]]; then
    echo "FAILED: no compile command for $sibling in $build/compile_commands.json"
    fails=$((fails + 1))
    continue
  fi
  check "$new compiles" bash -c "cd '$build' && $cmd"
done

if [[ $fails -ne 0 ]]; then
  echo "$fails checks failed"
  exit 1
fi
echo "new-filter.sh: every check passed"
