#!/bin/sh
# Puts printrun's printcore (the library behind Pronterface and pronsole) into DIR without its
# GUI dependencies: `apt-get download` of Debian's printrun-common and printcore packages,
# unpacked with dpkg-deb -x (no installation, no wxPython). Needs python3-serial (cmake/deps.sh).
# Prints the directory to put on PYTHONPATH. Fails, never skips, if it cannot fetch them.
set -eu
dir=${1:?usage: fetch-printcore.sh CACHE_DIR}
site="$dir/root/usr/lib/python3/dist-packages"
if [ ! -f "$site/printrun/printcore.py" ]; then
  mkdir -p "$dir/debs"
  # apt-get download writes into the working directory.
  (cd "$dir/debs" && apt-get download -q printrun-common printcore >/dev/null 2>"$dir/debs/apt.log") || {
    echo "fetch-printcore: apt-get download printrun-common printcore failed:" >&2
    cat "$dir/debs/apt.log" >&2
    exit 1
  }
  for deb in "$dir"/debs/*.deb; do dpkg-deb -x "$deb" "$dir/root"; done
fi
test -f "$site/printrun/printcore.py"
echo "$site"
