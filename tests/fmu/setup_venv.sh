#!/usr/bin/env bash
# Creates .venv at the repository root with what the FMU tests need (fmpy, pytest, numpy), unless
# it is already there. Needs python3 (3.11 tested) with venv and pip, and PyPI reachable.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
venv="$root/.venv"
python="${PYTHON:-$(command -v python3.11 || command -v python3)}"
if ! "$venv/bin/python" -c "import fmpy, pytest, numpy" 2>/dev/null; then
    "$python" -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet "fmpy>=0.3.20,<0.4" "pytest>=7" "numpy>=1.24"
fi
"$venv/bin/python" -c "import fmpy; print('fmpy', fmpy.__version__, 'in', '$venv')"
