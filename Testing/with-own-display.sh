#!/usr/bin/env bash
# Runs one command under an X server of its own, so that tests that render
# never share a display: a shared xvfb-run server resets when its last client
# disconnects and refuses a client that connects during the reset (issue 20:
# the plugin test failed 1 run in 3 beside the program's test). Xvfb picks a
# free display number itself (-displayfd), so servers started at the same
# moment cannot collide; -noreset keeps it up between the command's windows.
# Without Xvfb, an existing DISPLAY is used; with neither, exit 2 at once.
set -uo pipefail
if ! command -v Xvfb > /dev/null 2>&1; then
  if [ -n "${DISPLAY:-}" ]; then exec "$@"; fi
  echo "with-own-display: Xvfb not found and no DISPLAY: install xvfb" >&2
  exit 2
fi
dir="$(mktemp -d "${TMPDIR:-/tmp}/dg-xvfb.XXXXXX")"
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset \
  3> "$dir/display" > "$dir/xvfb.log" 2>&1 &
xpid=$!
cleanup() {
  kill "$xpid" 2> /dev/null && wait "$xpid" 2> /dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
# Xvfb writes the display number once it accepts connections.
for _ in $(seq 1 300); do
  if grep -q '^[0-9][0-9]*$' "$dir/display" 2> /dev/null; then break; fi
  if ! kill -0 "$xpid" 2> /dev/null; then
    echo "with-own-display: Xvfb exited at start:" >&2
    cat "$dir/xvfb.log" >&2
    exit 2
  fi
  sleep 0.1
done
if ! grep -q '^[0-9][0-9]*$' "$dir/display" 2> /dev/null; then
  echo "with-own-display: Xvfb gave no display within 30 s" >&2
  exit 2
fi
export DISPLAY=":$(head -n1 "$dir/display")"
"$@"
status=$?
exit $status
