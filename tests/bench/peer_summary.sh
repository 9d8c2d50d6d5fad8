#!/usr/bin/env bash
# peer_summary.sh -- one line per cell of a peer_table.sh output: each program's shortest time
# over the cell's runs, and the ratios of those shortest times (LIGGGHTS / libsinter and LAMMPS
# / libsinter on one thread, libsinter's 2-thread speed-up), then the median and the range of
# the per-run ratios. On a shared host whose load moves a run's time by up to 50 % (RESULTS.md,
# session 18), the shortest of a few interleaved runs is the closest to each program's own
# speed; a run's ratio compares two programs in the same minute, so the median of those is the
# measure least moved by the host's slow minutes (session 23); the range shows the spread.
#
#   tests/bench/peer_table.sh > table.txt; tests/bench/peer_summary.sh table.txt
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 PEER_TABLE_OUTPUT" >&2; exit 2; }
awk '
function val(field,   k) { for (k = 1; k <= NF; ++k) if (index($k, field "=") == 1) return substr($k, length(field) + 2); return "" }
function lo(a, b) { return (a == "" || b + 0 < a + 0) ? b : a }
function span(key, r) { if (!(key in rmin) || r < rmin[key]) rmin[key] = r; if (!(key in rmax) || r > rmax[key]) rmax[key] = r; ratio[key, ++nr[key]] = r }
function median(key,   n, a, i, j, t) {  # of the per-run ratios (insertion sort: mawk has no asort)
  n = nr[key]
  for (i = 1; i <= n; ++i) a[i] = ratio[key, i]
  for (i = 2; i <= n; ++i) for (j = i; j > 1 && a[j - 1] > a[j]; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
  return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
}
function cell_of(best, key) { return sprintf("%.2f / %.2f (%.2f-%.2f)", best, median(key), rmin[key], rmax[key]) }
/^#/ || NF == 0 { next }
{
  cell = $1 " N=" val("N") " heat=" val("heat")
  if (!(cell in seen)) { seen[cell] = 1; order[++cells] = cell }
  runs[cell]++
  lig = val("liggghts"); lmp = val("lammps"); one = val("one"); two = val("two")
  best_lig[cell] = lo(best_lig[cell], lig); best_one[cell] = lo(best_one[cell], one)
  best_two[cell] = lo(best_two[cell], two)
  span("lig " cell, lig / one); span("two " cell, one / two)
  if (lmp != "-") { best_lmp[cell] = lo(best_lmp[cell], lmp); span("lmp " cell, lmp / one) }
  lig2 = val("liggghts2")  # LIGGGHTS on two MPI ranks (peer_table.sh, LIG2=1)
  if (lig2 != "") { best_lig2[cell] = lo(best_lig2[cell], lig2); span("lig2 " cell, lig / lig2) }
  split(val("rss1_kB") "/" val("rss2_kB"), rss, "/"); mem[cell] = sprintf("%.0f / %.0f MB", rss[1] * 1.024e-3, rss[2] * 1.024e-3)
}
END {
  printf "# each ratio: of the shortest times / median of the runs (their range)\n"
  printf "%-26s %4s %-24s %-24s %-24s %s\n", "cell", "runs", "LIGGGHTS / 1T", "LAMMPS / 1T", "2T speed-up", "peak RSS 1T / 2T"
  for (c = 1; c <= cells; ++c) {
    k = order[c]
    l = cell_of(best_lig[k] / best_one[k], "lig " k)
    m = (k in best_lmp) ? cell_of(best_lmp[k] / best_one[k], "lmp " k) : "-"
    t = cell_of(best_one[k] / best_two[k], "two " k)
    printf "%-26s %4d %-24s %-24s %-24s %s", k, runs[k], l, m, t, mem[k]
    if (k in best_lig2) printf "   LIGGGHTS 2 ranks: %s", cell_of(best_lig[k] / best_lig2[k], "lig2 " k)
    printf "\n"
  }
}' "$1"
