# io/check_checkpoint.awk -- check a checkpoint.txt whole before FreeFEM reads it
# (FreeFEM aborts without a useful message on a malformed number).
# usage: CONTACT_RESTART=DIR awk -v scene=S -v nv=N -v nt=N -v ndof=N -v ncontact=N -v mesh=M -v cells=C -v nodes=D \
#            -v friction=F -v bodyfriction=B -v tangents=K -f run/numbers.awk -f io/check_checkpoint.awk FILE
#   (C, D: how the messages name the mesh's cells and nodes: triangles or tetrahedra, vertices or nodes)

# Format (io/checkpoint.idp, writeCheckpoint): one header line
#   checkpoint 6 SCENE STEP T NQP MAXPEN NV NT FINGERPRINT NDOF NCONTACT NEWTON NEWTON_RETRIES MAXSTRAIN GMRES
#                TOPOLOGY PARAMETERS_CHECKSUM DATA_CHECKSUM MAXPEN_OUTSIDE
#                ENERGY_GUARD_ON M0 SCALE0 WORK0 WORK_MAX GAIN_MAX GAIN_M GAIN_T   (watch/guards.idp)
# then u (NDOF values), v (NDOF values), the active set (NCONTACT values 0 or 1) and
# the contact multipliers (NCONTACT values); with friction (F = 1: contact/friction.idp) the stick set (0 or 1),
# the slip's signs (-1, 0 or 1; NCONTACT each), the tangential multipliers (K NCONTACT values, K = 1 on a plane body,
# 2 in 3D), the friction work and the foundation's (2 values) and the slip's directions (K NCONTACT values); with
# friction between bodies (B = 1: contact/body_friction.idp, without friction on a foundation) its work (1 value);
# each as FreeFEM writes an array (its size, then the values), then "end STEP".
# Prints one line "error: -restart DIR: ..." and exits 3 on the first defect.
BEGIN { name = ENVIRON["CONTACT_RESTART"] }     # (DIR from the environment: -v would read a '\' in it as an escape)
function fail(msg) { printf "error: -restart %s: %s\n", name, msg; failed = 1; exit 3 }
# a file cut anywhere (mid-number too) lacks its last line "end STEP": say so first
BEGIN {
  while ((getline line < ARGV[1]) > 0) { lines++; last = line }
  close(ARGV[1])
  if (lines > 1 && last !~ /^end [0-9]+$/)
    fail("checkpoint.txt is truncated (no end marker); the run was killed while writing it, or the disk was full")
}
NR == 1 {
  if ($1 != "checkpoint") fail("checkpoint.txt is not a checkpoint (empty or corrupt)")
  if ($2 != "6" || NF != 28) fail("checkpoint.txt has another format (written by another version); start a new run")
  if ($3 != scene) fail("it is a run of scene " $3 ", not " scene)
  if (!isint($4) || $4 + 0 < 1) fail("checkpoint.txt has no valid step ('" $4 "')")
  for (i = 5; i <= 28; i++) if (!isfinite($i)) fail("checkpoint.txt header field " i " is not a finite number ('" $i "')")
  if ($8 != nv || $9 != nt) fail("its checkpoint is for a mesh with " $8 " vertices and " $9 " " cells "; -mesh " mesh " has " nv " and " nt)
  if ($11 != ndof || $12 != ncontact) fail("checkpoint.txt is for " $11 " unknowns and " $12 " contact " nodes ", this mesh has " ndof " and " ncontact)
  step = $4; part = 0; expect = -1; parts = (friction ? 9 : 4) + (bodyfriction ? 1 : 0); next
}
{
  for (i = 1; i <= NF; i++) {
    tok = $i
    if (part == parts) { if (tok != "end") fail("checkpoint.txt has more values than its header announces"); part++; continue }
    if (part == parts + 1) { if (tok != step) fail("checkpoint.txt ends with 'end " tok "', its header says step " step); part++; continue }
    if (part == parts + 2) fail("checkpoint.txt goes on after its end marker")
    if (expect < 0) {
      want = (part < 2) ? ndof : ((part < 4 || (part < 6 && friction)) ? ncontact : ((part == 7) ? 2 : tangents * ncontact))
      if (bodyfriction && part == 4) want = 1
      if (tok != want) fail("checkpoint.txt is corrupt: array " part + 1 " has size '" tok "', expected " want)
      expect = want
      if (want == 0) { part++; expect = -1 }   # (a mesh without Gamma_C: no active set, no multipliers)
      continue
    }
    if (!isfinite(tok)) fail("checkpoint.txt is corrupt: '" substr(tok, 1, 30) "' is not a finite number")
    if ((part == 2 || (part == 4 && friction)) && tok != "0" && tok != "1") fail("checkpoint.txt is corrupt: an active-set entry is '" tok "'")
    if (part == 5 && friction && tok != "0" && tok != "1" && tok != "-1") fail("checkpoint.txt is corrupt: a slip's sign is '" tok "'")
    if (--expect == 0) { part++; expect = -1 }
  }
}
END {
  if (failed) exit 3
  if (NR == 0) fail("checkpoint.txt is empty")
  if (part != parts + 2) fail("checkpoint.txt is truncated (no end marker); the run was killed while writing it, or the disk was full")
}
