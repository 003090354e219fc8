#!/usr/bin/env bash
# Set up a development checkout: Chromium (Debian's package) for the viewer's browser tests when it is
# missing, then PARE with its test tools at the exact versions the suite was last tested with
# (requirements/dev.txt, refreshed by scripts/lock.sh). apt-get needs root (sudo is used when not root).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x /usr/bin/chromium ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq chromium
fi
# The lock constrains every package, so a machine that installed other versions earlier is brought back
# to the tested set instead of keeping (or newly resolving) whatever it had.
python -m pip install --quiet --constraint requirements/dev.txt -e ".[dev]"
