#!/usr/bin/env bash
# Set up a development checkout: Chromium (Debian's package) for the viewer's browser tests when it is
# missing, then PARE with its test tools. apt-get needs root (sudo is used when not root).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x /usr/bin/chromium ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq chromium
fi
pip install -e ".[dev]"
