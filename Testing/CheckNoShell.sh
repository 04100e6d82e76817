#!/usr/bin/env bash
# Fails when product code (not tests) calls anything that runs a command line or a program:
# no user string may ever reach a shell (Documentation/Reliability.md).
#   Testing/CheckNoShell.sh SOURCE_DIR
set -euo pipefail
cd "$1"
hits=$(grep -rnE '(^|[^A-Za-z0-9_.>])(system|popen|execl|execlp|execle|execv|execve|execvp|execvpe|posix_spawnp?|wordexp)\(' \
  --include='*.cxx' --include='*.cpp' --include='*.h' --include='*.hpp' \
  Applications Common Compute Filters IO Rendering || true)
if [ -n "$hits" ]; then
  echo "product code runs commands:"
  echo "$hits"
  exit 1
fi
echo "no command execution in product code"
