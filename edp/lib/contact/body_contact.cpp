// contact/body_contact.cpp -- a FreeFEM plugin (built by `make plugins` with ff-c++ into build/plugins/): the rows of
// the gap between plane bodies (docs/bodies.md), by the dual mortar method, and the true gap at every node.
//
// For bodies p < q, body p's boundary segments are the slave side and q's the master side. For each slave node j
// and master body q, the weighted gap
//     g_j = int_{Gamma_p} phi_j (x_p - x_q(pi(x_p))) . n_q ds >= 0
// over body p's segments that face body q's, x_q(pi) the closest point of the master segment and n_q its outward
// normal, phi_j the biorthogonal (dual) basis of the slave segment (2 N_a - N_b, 2 N_b - N_a where the master body
// covers it whole; on the covered part where it covers a part), by 3-point Gauss quadrature on each piece of a slave
// segment that a master segment covers (between its ends projected onto the slave segment). The segments, their
// overlaps, the normals and the closest points are frozen in the configuration given (the current one, or the
// step's iterate), so that g_j is linear in the displacement y = u^{n+1}: a row  c_j . y <= h_j. Each row's
// coefficients sum to int phi_j n on both bodies with opposite signs, so its force -c_j' lm_j is equal and opposite
// on the two bodies and the total momentum is conserved to round-off. Dual multipliers make the slave block of the
// rows diagonal: a uniform pressure has lm_j = p at every node (the contact patch test, docs/bodies.md).
//   long n = bodyContactRows(geometry, segments, settings, out)
//       geometry: [X1 (N), X2 (N), x1 (N), x2 (N)]: the nodes' reference and current coordinates (N nodes);
//       segments: [a, b, c, body] per boundary segment: its two nodes, the third node of its triangle (inside the
//                 body), its body (0, 1, ...);
//       settings: [the search distance: a slave segment takes the pieces of a master body that covers it when one
//                 of them is within it; a piece farther behind the master (its far side, through the body) is none];
//       a pair of segments whose outward normals are more than 60 degrees from opposite does not face: no row;
//       out: resized to [n, then per row: slave node, master body, h, D = int phi_j, entries, then per entry: node,
//            c_x, c_y (along the normal: the row), t_x, t_y (the same along the tangent t = (-n_y, n_x): the relative
//            tangential displacement weighted as the gap, friction's row)].
//       Candidates come from a bucket grid of the master segments (cells of the search distance's size at least).
//   real d = bodyNodeOverlap(geometry, segments, settings, where)
//       the largest overlap between bodies at a node (0 when none): over every node of a segment and every facing
//       segment of another body within the search distance, -(x - x(pi)) . n where positive; where: [the node,
//       the other body].
#include "ff++.hpp"
#include "AFunction_ext.hpp"
#include <algorithm>
#include <array>
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

// The master segments by bucket of a grid of cell size h (their bounding boxes grown by twice the search distance).
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
    double grow = 2 * distance;     // (a slave segment near a master body takes the body's covering pieces beyond it)
    double lx = std::min(s.x1[s.a[k]], s.x1[s.b[k]]) - grow, hx = std::max(s.x1[s.a[k]], s.x1[s.b[k]]) + grow;
    double ly = std::min(s.x2[s.a[k]], s.x2[s.b[k]]) - grow, hy = std::max(s.x2[s.a[k]], s.x2[s.b[k]]) + grow;
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
  // (each entry: the coefficients along n, x and y, then along the tangent t = (-n_y, n_x), x and y)
  std::map< std::pair< long, long >, std::map< long, std::array< double, 4 > > > entries;
  std::map< std::pair< long, long >, double > weight;    // D_j = int phi_j (Tresca's bound is g D_j)
  std::map< std::pair< long, long >, double > bound;
  struct Piece { long m; double s0, s1, sq[3], eta[3]; };
  for (long k = 0; k < s.n; ++k) {
    long sa = s.a[k], sb = s.b[k];
    double xa = s.x1[sa], ya = s.x2[sa], dx = s.x1[sb] - xa, dy = s.x2[sb] - ya, dd = dx * dx + dy * dy, len = std::sqrt(dd);
    // the pieces of this slave segment that master segments cover, and by master body the smallest |gap| at their
    // points: a body is taken whole (every piece of it) when that is within the search distance, so that a slave
    // segment near it is covered as far as the body covers it (a piece left out would leave the dual basis, which is
    // negative on part of the segment, a weighted gap of the wrong sign)
    std::vector< Piece > pieces;
    std::map< long, double > nearest;
    for (long m : candidates(s, g, k, true)) {
      double nx = s.nx[m], ny = s.ny[m];
      if (nx * s.nx[k] + ny * s.ny[k] > -0.5) continue;     // (surfaces that do not face each other, within 60 degrees)
      long ma = s.a[m], mb = s.b[m];
      // the piece [s0, s1] of the slave segment between the master segment's ends projected onto it (the master
      // segments of a body cover the slave segment without gap or overlap), and at each point the closest point of
      // the master segment, eta(s) = eta0 + s deta clipped to [0, 1]
      double ex = s.x1[mb] - s.x1[ma], ey = s.x2[mb] - s.x2[ma], ee = ex * ex + ey * ey;
      double eta0 = ((xa - s.x1[ma]) * ex + (ya - s.x2[ma]) * ey) / ee, deta = (dx * ex + dy * ey) / ee;
      double sA = ((s.x1[ma] - xa) * dx + (s.x2[ma] - ya) * dy) / dd, sB = ((s.x1[mb] - xa) * dx + (s.x2[mb] - ya) * dy) / dd;
      Piece p;
      p.m = m;
      p.s0 = std::max(std::min(sA, sB), 0.);  p.s1 = std::min(std::max(sA, sB), 1.);
      if (p.s1 - p.s0 <= 1e-14) continue;
      double closest = 1e300;
      bool farSide = false;
      for (int q = 0; q < 3; ++q) {
        p.sq[q] = p.s0 + (p.s1 - p.s0) * gaussPoint[q];
        double px = xa + p.sq[q] * dx, py = ya + p.sq[q] * dy;
        p.eta[q] = std::min(1., std::max(0., eta0 + p.sq[q] * deta));
        double gap = (px - s.x1[ma] - p.eta[q] * ex) * nx + (py - s.x2[ma] - p.eta[q] * ey) * ny;
        farSide = farSide || gap < -distance;              // (the master's far side, through the body)
        closest = std::min(closest, std::abs(gap));
      }
      if (farSide) continue;
      pieces.push_back(p);
      long body = s.body[m];
      nearest[body] = nearest.count(body) ? std::min(nearest[body], closest) : closest;
    }
    // by master body near it: the dual basis of the part of the slave segment the body covers (consistent dual
    // shape functions, Cichosz and Bischoff 2011): phi_r = A_r0 N_a + A_r1 N_b, A = D M^-1 with M_ij = int N_i N_j and
    // D = diag(int N_j) over the covered pieces, so that int phi_r N_j = delta_rj int N_j there. On a segment covered
    // whole, phi_a = 2 N_a - N_b; on a part, the weighted gap keeps the sign of the gap's nodal values (a piece
    // missing would otherwise leave a gap of the wrong sign: the whole segment's dual basis is negative on a third)
    for (auto &nb : nearest) {
      if (nb.second > distance) continue;
      long body = nb.first;
      double M00 = 0, M01 = 0, M11 = 0, D0 = 0, D1 = 0;
      for (const Piece &p : pieces) {
        if (s.body[p.m] != body) continue;
        for (int q = 0; q < 3; ++q) {
          double w = gaussWeight[q] * (p.s1 - p.s0) * len, t = p.sq[q];
          M00 += w * (1 - t) * (1 - t);  M01 += w * (1 - t) * t;  M11 += w * t * t;  D0 += w * (1 - t);  D1 += w * t;
        }
      }
      double det = M00 * M11 - M01 * M01;
      if (!(det > 1e-12 * (M00 + M11) * (M00 + M11))) continue;     // (a sliver of the segment covered: no row from it)
      const double A[2][2] = {{D0 * M11 / det, -D0 * M01 / det}, {-D1 * M01 / det, D1 * M00 / det}};
      std::pair< long, long > rowA(sa, body), rowB(sb, body);
      for (const Piece &p : pieces) {
        if (s.body[p.m] != body) continue;
        long m = p.m, ma = s.a[m], mb = s.b[m];
        double nx = s.nx[m], ny = s.ny[m];
        for (int q = 0; q < 3; ++q) {
          double w = gaussWeight[q] * (p.s1 - p.s0) * len, t = p.sq[q], e = p.eta[q];
          double gapRef = (s.X1[sa] + t * (s.X1[sb] - s.X1[sa]) - s.X1[ma] - e * (s.X1[mb] - s.X1[ma])) * nx
                          + (s.X2[sa] + t * (s.X2[sb] - s.X2[sa]) - s.X2[ma] - e * (s.X2[mb] - s.X2[ma])) * ny;
          const std::pair< long, long > rows[2] = {rowA, rowB};
          const double phi[2] = {A[0][0] * (1 - t) + A[0][1] * t, A[1][0] * (1 - t) + A[1][1] * t};   // the dual basis
          const long nodes[4] = {sa, sb, ma, mb};
          const double shape[4] = {-(1 - t), -t, 1 - e, e};      // -N on the slave, +N on the master
          for (int r = 0; r < 2; ++r) {
            std::map< long, std::array< double, 4 > > &row = entries[rows[r]];
            for (int i = 0; i < 4; ++i) {
              double c = w * phi[r] * shape[i];
              std::array< double, 4 > &e = row[nodes[i]];
              e[0] += c * nx;  e[1] += c * ny;  e[2] -= c * ny;  e[3] += c * nx;
            }
            bound[rows[r]] += w * phi[r] * gapRef;
            weight[rows[r]] += w * phi[r];
          }
        }
      }
    }
  }
  long size = 1;
  for (auto &row : entries) size += 5 + 5 * row.second.size( );
  out->resize(size);
  KN< double > &o = *out;
  long p = 0;
  o[p++] = entries.size( );
  for (auto &row : entries) {
    o[p++] = row.first.first;
    o[p++] = row.first.second;
    o[p++] = bound[row.first];
    o[p++] = weight[row.first];
    o[p++] = row.second.size( );
    for (auto &e : row.second) { o[p++] = e.first;  for (int k = 0; k < 4; ++k) o[p++] = e.second[k]; }
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
