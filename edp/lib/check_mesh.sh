#!/bin/sh
# check_mesh.sh NAME FILE -- called by mesh.idp before gmshload: one line
# "error: -mesh NAME: ..." and exit 3 for a missing file or a defective mesh
# (check_mesh.awk), silent with exit 0 otherwise.
[ -f "$2" ] && [ -r "$2" ] || { echo "error: -mesh $1: file missing or unreadable"; exit 3; }
exec awk -v name="$1" -f "$(dirname "$0")/check_mesh.awk" "$2"
