# solve/ffddm_without_mumps.sh DIR -- FreeFEM's ffddm*.idp copied into DIR without their line
# `load "MUMPS_mpi"`: Debian does not ship MUMPS_mpi.so, and with that line `include "ffddm.idp"` stops
# every run ("Load error: MUMPS_mpi"); the subdomains' solves here are CHOLMOD's or UMFPACK's
# (solve/ffddm_solve.idp, docs/parallel.md). edp/run.sh puts DIR first on FF_INCLUDEPATH for -np N.
mkdir "$1" || exit 1
for f in /usr/include/freefem++/idp/ffddm*.idp; do
  sed '/^[[:space:]]*load[[:space:]]*"MUMPS_mpi"/d' "$f" > "$1/${f##*/}" || exit 1
done
