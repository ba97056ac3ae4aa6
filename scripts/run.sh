#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job. Arguments are passed
# to the program; with none it runs on its built-in shape. Results go to out/.
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/setup.sh"
mkdir -p "$DG_ROOT/out"
export VTK_SMP_BACKEND_IN_USE="${VTK_SMP_BACKEND_IN_USE:-STDThread}"
PROGRAM=("$DG_BUILD/bin/piecewise-normals" --output-dir "$DG_ROOT/out" "$@")
# The picture is rendered off-screen, which Debian's VTK does through GLX:
# without a display, give it a virtual one.
if [ -z "${DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1920x1080x24" "${PROGRAM[@]}"
fi
exec "${PROGRAM[@]}"
