#!/bin/sh
# A stand-in for Karamelo in the peer-comparison test: reads run(N) and set_output from the input
# file given by -i, and prints what Karamelo prints around its loop (the log header, the step-0 and
# step-N lines, each field followed by a tab, its particle count and its wall time), with a pause
# of N milliseconds in between as the loop.
[ "$1" = "-i" ] || { echo "Usage: karamelo -i input_file"; exit 1; }
steps=$(sed -n 's/^run(\([0-9]*\))$/\1/p' "$2")
[ -n "$steps" ] || { echo "no run() in $2"; exit 1; }
printf 'np_local=750\n'
printf 'Step\tdt\tTime\t\n0\t1e-08\t0\t\n'
sleep "$(awk "BEGIN { print $steps / 1000 }")"
printf '%s\t1e-08\t%s\t\n' "$steps" "$(awk "BEGIN { print $steps * 1e-8 }")"
printf 'Total wall time: 0:0:0\n'
