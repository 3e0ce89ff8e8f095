#!/bin/bash
# One hand-made weakening of the proof code, tested on a throw-away export of HEAD.
#   bench/hand_mutant.sh FILE 'OLD TEXT' 'NEW TEXT' [TEST FILES...]
# FILE is relative to the repository; OLD TEXT must occur exactly once; the tests run with
# PYTHONPATH pointing at the export (bench/mutation_check.py does the same for many mutants).
set -euo pipefail
root=$(git -C "$(dirname "$0")" rev-parse --show-toplevel)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
git -C "$root" archive HEAD | tar -x -C "$work"
file=$1 old=$2 new=$3
shift 3
python3 - "$work/$file" "$old" "$new" <<'PY'
import sys
path, old, new = sys.argv[1:]
text = open(path).read()
assert text.count(old) == 1, f"{old!r} occurs {text.count(old)} times in {path}"
open(path, "w").write(text.replace(old, new))
PY
cd "$work"
OPENBLAS_NUM_THREADS=1 PYTHONPATH="$work" "${PYTHON:-python}" -m pytest -x -q -p no:cacheprovider "$@" | tail -1
