// SPDX-License-Identifier: MIT
// @ts-check
// What the page reads from a volspline-tspline JSON (the spline download): each control point's
// anchor, and the control lattice joining neighbouring anchors.

/**
 * The anchors and lattice of a spline. A function's anchor is the middle knot of each of its
 * three local knot vectors (Eq. 4.3: the T-mesh vertex it sits on), as a fraction of the domain;
 * its lattice neighbour along axis a is the function anchored at the next knot of that vector
 * (the T-mesh edge's other end), if one is.
 * @param {Uint8Array} bytes the spline JSON
 * @returns {{uvw: Float32Array, edges: Uint32Array}} uvw: 3 per control point, in the order of the
 *   spline's points; edges: pairs of control point indices
 */
export function splineLattice(bytes) {
  const spline = JSON.parse(new TextDecoder().decode(bytes));
  const lo = spline.domain_min, hi = spline.domain_max;
  const functions = spline.functions;
  const uvw = new Float32Array(3 * functions.length);
  const index = new Map();
  const key = (u, v, w) => `${u},${v},${w}`;
  functions.forEach((f, i) => {
    for (let a = 0; a < 3; a++) uvw[3 * i + a] = (f.knots[a][2] - lo[a]) / (hi[a] - lo[a] || 1);
    index.set(key(f.knots[0][2], f.knots[1][2], f.knots[2][2]), i);
  });
  const edges = [];
  functions.forEach((f, i) => {
    for (let a = 0; a < 3; a++) {
      const anchor = [f.knots[0][2], f.knots[1][2], f.knots[2][2]];
      if (f.knots[a][3] === anchor[a]) continue;  // a repeated knot: the domain's end
      anchor[a] = f.knots[a][3];
      const j = index.get(key(anchor[0], anchor[1], anchor[2]));
      if (j !== undefined) edges.push(i, j);
    }
  });
  return { uvw, edges: new Uint32Array(edges) };
}
