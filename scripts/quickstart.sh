#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Quick start: install the tools (as root), build the library, then run the main job (the
# parting analysis of the bundled cup with a hole: report, .FCStd and PNGs rendered by
# FreeCAD's GUI), then the point-classification demo on the bundled bracket.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
bash examples/run_demo.sh
