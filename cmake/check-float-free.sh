#!/bin/sh
# Fails the build when a firmware image links soft-float routines: the firmware is fixed point.
nm="$1"; elf="$2"
if "$nm" "$elf" | grep -E ' (__addsf3|__subsf3|__mulsf3|__divsf3|__fixsfsi|__fixunssfsi|__floatsisf|__floatunsisf|__cmpsf2|__extendsfdf2)$'; then
  echo "error: $elf links soft-float routines (above); the firmware must be fixed point" >&2
  exit 1
fi
