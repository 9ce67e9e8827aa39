#!/usr/bin/env bash
# The project speaks of itself alone: the sources, tests and docs name no session of
# its development (history lives in git log). ctest runs this (wording.no_session_history).
set -euo pipefail
cd "$(dirname "$0")/.."
pattern='session [0-9]|session.s |sessions [0-9]'
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  hits=$(git grep -nIiE "$pattern" -- . ':!scripts/check_wording.sh' || true)
else
  hits=$(grep -rnIiE "$pattern" --exclude-dir=build --exclude-dir=.git --exclude=check_wording.sh . || true)
fi
if [ -n "$hits" ]; then
  echo "Lines that speak of development sessions (say what the code does and why, by geometry or physics):"
  echo "$hits"
  exit 1
fi
echo "no session history in the sources, tests and docs"
