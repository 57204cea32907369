#!/usr/bin/env bash
# The app's first frame as a whole process: starts BINARY in tmux (120×40)
# on the decks in DECKS with the data folder DATA, waits until the screen
# shows TEXT, and prints the milliseconds from the start and the process's
# peak memory (VmHWM). Run it twice on the same DATA to see a start after
# the deck cache was written. Needs tmux.
#
#   benches/first_frame.sh target/release/flipcard DIR/decks DATA "A big deck"
set -euo pipefail
bin=$1 decks=$2 data=$3 text=$4
mkdir -p "$data"
session=first-frame-$$
start=$(date +%s%N)
tmux new-session -d -s "$session" -x 120 -y 40 \
  "HOME=$data FLIPCARD_DATA_DIR=$data/data FLIPCARD_CONFIG=$data/config.toml FLIPCARD_DECKS=$decks $bin"
trap 'tmux kill-session -t "$session" 2>/dev/null || true' EXIT
for _ in $(seq 1 6000); do
  if tmux capture-pane -p -t "$session" 2>/dev/null | grep -qF "$text"; then
    end=$(date +%s%N)
    pid=$(tmux list-panes -t "$session" -F '#{pane_pid}')
    echo "first frame: $(((end - start) / 1000000)) ms, $(grep VmHWM "/proc/$pid/status" | tr -s ' \t' ' ')"
    exit 0
  fi
  sleep 0.003
done
echo "first frame: \"$text\" never shown" >&2
exit 1
