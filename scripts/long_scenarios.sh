#!/usr/bin/env bash
# Prints the regex of the long scenario sets (tests/long_scenarios.txt) for ctest -E.
set -euo pipefail
cd "$(dirname "$0")/.."
grep -v '^#' tests/long_scenarios.txt | grep -v '^$' | paste -sd'|'
