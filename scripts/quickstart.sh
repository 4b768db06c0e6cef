#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Quick start, step 1: install and build, then run the main job (the point-classification
# demo on the bundled example part: report, .FCStd and a PNG rendered by FreeCAD's GUI).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash examples/run_demo.sh
