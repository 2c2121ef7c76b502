#!/bin/sh
# Instructions per frame (callgrind, one thread) of the core crate's frame_cost example, for
# A/B comparisons that a noisy machine cannot blur. Usage:
#   bench/instruction_counts.sh BINARY [BINARY ...]
# e.g. cp target/release/examples/frame_cost /tmp/before; (change, rebuild);
#      bench/instruction_counts.sh /tmp/before target/release/examples/frame_cost
set -eu
CONFIGS="flat 99 1080 lights=sun
gouraud 12 1080 lights=sun
gouraud 99 1080 lights=sun,point
phong 12 1080 lights=sun
phong 99 1080 lights=sun,point
phong 99 1080 lights=spot,area
phong 99 1080 lights=sun fog depth two-sided
phong 99 1080 plane lights=sun shadows=map
gouraud 99 1080 lights=sun fog depth f32"
printf '%-45s' "config (frames=1)"
for b in "$@"; do printf ' %16s' "$(basename "$b")"; done
echo
echo "$CONFIGS" | while read -r cfg; do
  printf '%-45s' "$cfg"
  for b in "$@"; do
    n=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null "$b" $cfg frames=1 2>&1 \
        | sed -n 's/.*Collected : *\([0-9]*\).*/\1/p')
    printf ' %16s' "$n"
  done
  echo
done
