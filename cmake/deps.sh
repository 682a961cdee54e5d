#!/bin/sh
# Installs the Debian packages this project needs, only those that are missing.
# Used by README's two commands and by .ci/run; safe to run again.
set -e
pkgs="cmake g++ make gcc-avr avr-libc binutils-avr simavr libsimavr-dev libelf-dev libgtest-dev clang libclang-rt-dev python3-serial"
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
echo "installing:$missing"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q >/dev/null || true
$sudo apt-get install -y -q --no-install-recommends $missing >/dev/null
