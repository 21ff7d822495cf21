#!/bin/sh
# make demo: the dam break in a window when a display can be opened, else headless for 3
# simulated seconds with a screenshot. A DISPLAY that cannot be opened (a stale ssh or
# container variable) falls back to headless with a line saying so.
cd "$(dirname "$0")/.." || exit 2
seiche=build/bin/seiche
scene=scripts/scenes/dam_break.lua
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
    "$seiche" "$scene" 2>build/demo-window.err
    status=$?
    if ! grep -q "cannot open a window" build/demo-window.err; then
        cat build/demo-window.err >&2
        exit $status
    fi
    echo "demo: the display '${DISPLAY:-$WAYLAND_DISPLAY}' cannot be opened; running headless instead"
else
    echo "demo: no display; running headless for 3 simulated seconds"
fi
"$seiche" --headless --frames 180 --screenshot build/dam_break.png "$scene" || exit $?
echo "demo: screenshot written to build/dam_break.png"
