#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Development setup on Debian 12: installs the tools (scripts/install-deps.sh, as root) and
# builds libmfgeom.so into build/ (scripts/build.sh, which alone needs only cmake and cc).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
