#!/usr/bin/env bash
# Refresh the locks: the newest versions pyproject.toml's ranges allow, resolved for every platform with
# Python 3.11 as the floor. requirements/core.txt pins the plain install, requirements/dev.txt the one
# scripts/setup-dev.sh makes (every extra and the test tools). Run the whole suite after refreshing, and
# commit the locks with any fix the new versions need.
set -euo pipefail
cd "$(dirname "$0")/.."
python -m pip install --quiet "uv>=0.9"
common=(--universal --python-version 3.11 --quiet)
python -m uv pip compile "${common[@]}" pyproject.toml -o requirements/core.txt
python -m uv pip compile "${common[@]}" pyproject.toml --extra dev -o requirements/dev.txt
echo "locks written: requirements/core.txt, requirements/dev.txt"
