// contact/body_contact.cpp -- a FreeFEM plugin (built by `make plugins` with ff-c++ into build/plugins/): the rows of
// the gap between plane bodies (docs/bodies.md), by the dual mortar method, and the true gap at every node.
//
// For bodies p < q, body p's boundary segments are the slave side and q's the master side. For each slave node j
// and master body q, the weighted gap
//     g_j = int_{Gamma_p} phi_j (x_p - x_q(pi(x_p))) . n_q ds >= 0
// over body p's segments that face body q's, x_q(pi) the closest point of the master segment and n_q its outward
// normal, phi_j the biorthogonal (dual) basis 2 N_a - N_b, 2 N_b - N_a of the slave segment, by 3-point Gauss
// quadrature on each piece of a slave segment that a master segment covers (its ends projected). The segments,
// their overlaps, the normals and the closest points are frozen in the configuration given (the current one, or
// the step's iterate), so that g_j is linear in the displacement y = u^{n+1}: a row  c_j . y <= h_j. Each row's
// coefficients sum to int phi_j n on both bodies with opposite signs, so its force -c_j' lm_j is equal and opposite
// on the two bodies and the total momentum is conserved to round-off. Dual multipliers make the slave block of the
// rows diagonal: a uniform pressure has lm_j = p at every node (the contact patch test, docs/bodies.md).
//
//   long n = bodyContactRows(geometry, segments, settings, out)
//       geometry: [X1 (N), X2 (N), x1 (N), x2 (N)]: the nodes' reference and current coordinates (N nodes);
//       segments: [a, b, c, body] per boundary segment: its two nodes, the third node of its triangle (inside the
//                 body), its body (0, 1, ...);
//       settings: [the search distance: a master segment farther than it from the slave piece, in front or behind
//                 (its far side), is no candidate];
//       a pair of segments whose outward normals are more than 60 degrees from opposite does not face: no row;
//       out: resized to [n, then per row: slave node, master body, h, entries, (node, c_x, c_y) per entry].
//       Candidates come from a bucket grid of the master segments (cells of the search distance's size at least).
//   real d = bodyNodeOverlap(geometry, segments, settings, where)
//       the largest overlap between bodies at a node (0 when none): over every node of a segment and every facing
//       segment of another body within the search distance, -(x - x(pi)) . n where positive; where: [the node,
//       the other body].
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <vector>

namespace {
struct Segments {
  long n = 0, nodes = 0;
  std::vector< long > a, b, body;
  std::vector< double > nx, ny;    // the outward unit normal, current configuration
  const double *X1, *X2, *x1, *x2;
};

Segments readSegments(KN< double > *geometry, KN< long > *segments) {
  Segments s;
  if (geometry->N( ) % 4 != 0 || segments->N( ) % 4 != 0) ExecError("body_contact: geometry or segments has the wrong size");
  if (geometry->step != 1) ExecError("body_contact: geometry is not contiguous");
  s.nodes = geometry->N( ) / 4;
  s.n = segments->N( ) / 4;
  const double *g = *geometry;
  s.X1 = g;  s.X2 = g + s.nodes;  s.x1 = g + 2 * s.nodes;  s.x2 = g + 3 * s.nodes;
  for (long k = 0; k < s.n; ++k) {
    long a = (*segments)[4 * k], b = (*segments)[4 * k + 1], c = (*segments)[4 * k + 2], body = (*segments)[4 * k + 3];
    if (a < 0 || b < 0 || c < 0 || a >= s.nodes || b >= s.nodes || c >= s.nodes) ExecError("body_contact: a segment's node is out of range");
    double dx = s.x1[b] - s.x1[a], dy = s.x2[b] - s.x2[a], len = std::hypot(dx, dy);
    double nx = dy / len, ny = -dx / len;
    if (nx * (s.x1[c] - s.x1[a]) + ny * (s.x2[c] - s.x2[a]) > 0) { nx = -nx;  ny = -ny; }
    s.a.push_back(a);  s.b.push_back(b);  s.body.push_back(body);  s.nx.push_back(nx);  s.ny.push_back(ny);
  }
  return s;
}

// The master segments by bucket of a grid of cell size h (their bounding boxes grown by the search distance).
struct Grid {
  double h, x0, y0;
  std::unordered_map< long long, std::vector< long > > cells;
  long long key(long i, long j) const { return (long long)i * 2000003LL + j; }
  long cellOf(double v, double origin) const { return (long)std::floor((v - origin) / h); }
};

Grid gridOf(const Segments &s, double distance) {
  Grid g;
  double longest = 0, x0 = 1e300, y0 = 1e300;
  for (long k = 0; k < s.n; ++k) {
    longest = std::max(longest, std::hypot(s.x1[s.b[k]] - s.x1[s.a[k]], s.x2[s.b[k]] - s.x2[s.a[k]]));
    x0 = std::min(x0, std::min(s.x1[s.a[k]], s.x1[s.b[k]]));
    y0 = std::min(y0, std::min(s.x2[s.a[k]], s.x2[s.b[k]]));
  }
  g.h = std::max(longest, distance);
  if (!(g.h > 0)) g.h = 1;
  g.x0 = x0 - 2 * g.h;  g.y0 = y0 - 2 * g.h;
  for (long k = 0; k < s.n; ++k) {
    double lx = std::min(s.x1[s.a[k]], s.x1[s.b[k]]) - distance, hx = std::max(s.x1[s.a[k]], s.x1[s.b[k]]) + distance;
    double ly = std::min(s.x2[s.a[k]], s.x2[s.b[k]]) - distance, hy = std::max(s.x2[s.a[k]], s.x2[s.b[k]]) + distance;
    for (long i = g.cellOf(lx, g.x0); i <= g.cellOf(hx, g.x0); ++i)
      for (long j = g.cellOf(ly, g.y0); j <= g.cellOf(hy, g.y0); ++j) g.cells[g.key(i, j)].push_back(k);
  }
  return g;
}

// The master segments of bodies other than body (above it when above) whose grown boxes share a cell with segment k's.
std::vector< long > candidates(const Segments &s, const Grid &g, long k, bool above) {
  std::vector< long > out;
  double lx = std::min(s.x1[s.a[k]], s.x1[s.b[k]]), hx = std::max(s.x1[s.a[k]], s.x1[s.b[k]]);
  double ly = std::min(s.x2[s.a[k]], s.x2[s.b[k]]), hy = std::max(s.x2[s.a[k]], s.x2[s.b[k]]);
  for (long i = g.cellOf(lx, g.x0); i <= g.cellOf(hx, g.x0); ++i)
    for (long j = g.cellOf(ly, g.y0); j <= g.cellOf(hy, g.y0); ++j) {
      auto it = g.cells.find(g.key(i, j));
      if (it == g.cells.end( )) continue;
      for (long m : it->second)
        if ((above ? s.body[m] > s.body[k] : s.body[m] != s.body[k])) out.push_back(m);
    }
  std::sort(out.begin( ), out.end( ));
  out.erase(std::unique(out.begin( ), out.end( )), out.end( ));
  return out;
}

const double gaussPoint[3] = {0.5 - 0.3872983346207417, 0.5, 0.5 + 0.3872983346207417};
const double gaussWeight[3] = {5. / 18, 8. / 18, 5. / 18};

long bodyContactRows(KN< double > *const &geometry, KN< long > *const &segments, KN< double > *const &settings,
                     KN< double > *const &out) {
  Segments s = readSegments(geometry, segments);
  double distance = (*settings)[0];
  Grid g = gridOf(s, distance);
  // rows by (slave node, master body), in that order; each row's entries by node
  std::map< std::pair< long, long >, std::map< long, std::pair< double, double > > > entries;
  std::map< std::pair< long, long >, double > bound;
  for (long k = 0; k < s.n; ++k) {
    long sa = s.a[k], sb = s.b[k];
    double xa = s.x1[sa], ya = s.x2[sa], dx = s.x1[sb] - xa, dy = s.x2[sb] - ya, dd = dx * dx + dy * dy, len = std::sqrt(dd);
    for (long m : candidates(s, g, k, true)) {
      double nx = s.nx[m], ny = s.ny[m];
      if (nx * s.nx[k] + ny * s.ny[k] > -0.5) continue;     // (surfaces that do not face each other, within 60 degrees)
      long ma = s.a[m], mb = s.b[m];
      double pa = ((s.x1[ma] - xa) * dx + (s.x2[ma] - ya) * dy) / dd, pb = ((s.x1[mb] - xa) * dx + (s.x2[mb] - ya) * dy) / dd;
      double s0 = std::max(std::min(pa, pb), 0.), s1 = std::min(std::max(pa, pb), 1.);
      if (s1 - s0 <= 1e-14) continue;
      double ex = s.x1[mb] - s.x1[ma], ey = s.x2[mb] - s.x2[ma], ee = ex * ex + ey * ey;
      double sq[3], eta[3], gapNow[3];
      bool near = false;
      for (int q = 0; q < 3; ++q) {
        sq[q] = s0 + (s1 - s0) * gaussPoint[q];
        double px = xa + sq[q] * dx, py = ya + sq[q] * dy;
        eta[q] = std::min(1., std::max(0., ((px - s.x1[ma]) * ex + (py - s.x2[ma]) * ey) / ee));
        gapNow[q] = (px - s.x1[ma] - eta[q] * ex) * nx + (py - s.x2[ma] - eta[q] * ey) * ny;
        near = near || std::abs(gapNow[q]) <= distance;    // (a gap below -distance: the master's far side)
      }
      if (!near) continue;
      std::pair< long, long > rowA(sa, s.body[m]), rowB(sb, s.body[m]);
      for (int q = 0; q < 3; ++q) {
        double w = gaussWeight[q] * (s1 - s0) * len, t = sq[q], e = eta[q];
        double gapRef = (s.X1[sa] + t * (s.X1[sb] - s.X1[sa]) - s.X1[ma] - e * (s.X1[mb] - s.X1[ma])) * nx
                        + (s.X2[sa] + t * (s.X2[sb] - s.X2[sa]) - s.X2[ma] - e * (s.X2[mb] - s.X2[ma])) * ny;
        const std::pair< long, long > rows[2] = {rowA, rowB};
        const double phi[2] = {2 - 3 * t, 3 * t - 1};           // the dual basis of the slave segment
        const long nodes[4] = {sa, sb, ma, mb};
        const double shape[4] = {-(1 - t), -t, 1 - e, e};      // -N on the slave, +N on the master
        for (int r = 0; r < 2; ++r) {
          std::map< long, std::pair< double, double > > &row = entries[rows[r]];
          for (int i = 0; i < 4; ++i) {
            double c = w * phi[r] * shape[i];
            row[nodes[i]].first += c * nx;
            row[nodes[i]].second += c * ny;
          }
          bound[rows[r]] += w * phi[r] * gapRef;
        }
      }
    }
  }
  long size = 1;
  for (auto &row : entries) size += 4 + 3 * row.second.size( );
  out->resize(size);
  KN< double > &o = *out;
  long p = 0;
  o[p++] = entries.size( );
  for (auto &row : entries) {
    o[p++] = row.first.first;
    o[p++] = row.first.second;
    o[p++] = bound[row.first];
    o[p++] = row.second.size( );
    for (auto &e : row.second) { o[p++] = e.first;  o[p++] = e.second.first;  o[p++] = e.second.second; }
  }
  return entries.size( );
}

double bodyNodeOverlap(KN< double > *const &geometry, KN< long > *const &segments, KN< double > *const &settings,
                       KN< double > *const &where) {
  Segments s = readSegments(geometry, segments);
  double distance = (*settings)[0], most = 0;
  Grid g = gridOf(s, distance);
  where->resize(2);
  (*where)[0] = -1;  (*where)[1] = -1;
  for (long k = 0; k < s.n; ++k)
    for (long m : candidates(s, g, k, false)) {
      if (s.nx[m] * s.nx[k] + s.ny[m] * s.ny[k] > -0.5) continue;
      long ma = s.a[m], mb = s.b[m];
      double ex = s.x1[mb] - s.x1[ma], ey = s.x2[mb] - s.x2[ma], ee = ex * ex + ey * ey;
      for (long node : {s.a[k], s.b[k]}) {
        double rx = s.x1[node] - s.x1[ma], ry = s.x2[node] - s.x2[ma], eta = (rx * ex + ry * ey) / ee;
        if (eta < 0 || eta > 1) continue;                  // (its closest point is another segment's)
        double gap = (rx - eta * ex) * s.nx[m] + (ry - eta * ey) * s.ny[m];
        if (gap < -distance) continue;                     // (beyond the search: the far side)
        if (-gap > most) { most = -gap;  (*where)[0] = node;  (*where)[1] = s.body[m]; }
      }
    }
  return most;
}
}    // namespace

static void Load_Init( ) {
  Global.Add("bodyContactRows", "(",
             new OneOperator4_< long, KN< double > *, KN< long > *, KN< double > *, KN< double > * >(bodyContactRows));
  Global.Add("bodyNodeOverlap", "(",
             new OneOperator4_< double, KN< double > *, KN< long > *, KN< double > *, KN< double > * >(bodyNodeOverlap));
}

LOADFUNC(Load_Init)
