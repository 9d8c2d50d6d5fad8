#!/usr/bin/env bash
# peer_summary.sh -- one line per cell of a peer_table.sh output: each program's shortest time
# over the cell's runs, and the ratios of those shortest times (LIGGGHTS / libsinter and LAMMPS
# / libsinter on one thread, libsinter's 2-thread speed-up), beside the range of the per-run
# ratios. On a shared host whose load moves a run's time by up to 50 % (RESULTS.md, session
# 18), the shortest of a few interleaved runs is the closest to each program's own speed; the
# per-run ranges show the spread it was taken from.
#
#   tests/bench/peer_table.sh > table.txt; tests/bench/peer_summary.sh table.txt
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 PEER_TABLE_OUTPUT" >&2; exit 2; }
awk '
function val(field,   k) { for (k = 1; k <= NF; ++k) if (index($k, field "=") == 1) return substr($k, length(field) + 2); return "" }
function lo(a, b) { return (a == "" || b + 0 < a + 0) ? b : a }
function span(key, r) { if (!(key in rmin) || r < rmin[key]) rmin[key] = r; if (!(key in rmax) || r > rmax[key]) rmax[key] = r }
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
  split(val("rss1_kB") "/" val("rss2_kB"), rss, "/"); mem[cell] = sprintf("%.0f / %.0f MB", rss[1] * 1.024e-3, rss[2] * 1.024e-3)
}
END {
  printf "%-30s %5s %20s %20s %20s %s\n", "cell", "runs", "LIGGGHTS/1T best (all)", "LAMMPS/1T best (all)", "2T speed-up best (all)", "peak RSS 1T / 2T"
  for (c = 1; c <= cells; ++c) {
    k = order[c]
    l = sprintf("%.2f (%.2f-%.2f)", best_lig[k] / best_one[k], rmin["lig " k], rmax["lig " k])
    m = (k in best_lmp) ? sprintf("%.2f (%.2f-%.2f)", best_lmp[k] / best_one[k], rmin["lmp " k], rmax["lmp " k]) : "-"
    t = sprintf("%.2f (%.2f-%.2f)", best_one[k] / best_two[k], rmin["two " k], rmax["two " k])
    printf "%-30s %5d %20s %20s %20s %s\n", k, runs[k], l, m, t, mem[k]
  }
}' "$1"
