// SPDX-License-Identifier: MIT
// splineQuality(json, meshBytes, meshName, options): the scaled-Jacobian histogram counts every
// lattice point once and agrees with the folded points; an identity spline of the unit cube
// (built here: a 4×4×4 tensor B-spline with its control points at the Greville abscissae) has
// scaled J = 1 everywhere, and its boundary is at distance 0 from the cube's surface mesh.
'use strict';
module.exports = function (vs, { check, sourceDir, fs, path }) {
  if (typeof vs.splineQuality !== 'function') { check(false, 'splineQuality is exported'); return; }
  const text = (s) => new TextEncoder().encode(s);
  // Cubic B-splines on [0, 1] with one inner knot at 1/2: knots 0,0,0,0,.5,1,1,1,1; 5 functions,
  // Greville abscissae 0, 1/6, 1/2, 5/6, 1 (so F(u) = u: linear precision).
  const knots = [0, 0, 0, 0, 0.5, 1, 1, 1, 1];
  const functions = [];
  const greville = (i) => (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3;
  for (let k = 0; k < 5; k++)
    for (let j = 0; j < 5; j++)
      for (let i = 0; i < 5; i++)
        functions.push({ knots: [knots.slice(i, i + 5), knots.slice(j, j + 5), knots.slice(k, k + 5)], weight: 1, point: [greville(i), greville(j), greville(k)] });
  const json = text(JSON.stringify({ format: 'volspline-tspline', version: 1, form: 'semi-standard', dimension: 3, domain_min: [0, 0, 0], domain_max: [1, 1, 1], functions }));
  const cube = text('OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n' +
                    '3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n');
  const q = vs.splineQuality(json, cube, 'cube.off', { lattice: 6, bins: 10, preview_samples: 5 });
  check(q.ok === true, 'splineQuality on an identity spline: ' + q.message);
  if (q.ok) {
    const total = Array.from(q.counts).reduce((a, b) => a + b, 0);
    check(q.samples === 216 && total === 216 && q.counts.length === 10, `histogram counts the 6³ lattice once (${total})`);
    check(q.counts[9] === 216 && Math.abs(q.min_scaled_jacobian - 1) < 1e-12 && q.folded.length === 0,
          `identity: every scaled J in the top bin, min ${q.min_scaled_jacobian}, no folded points`);
    check(q.boundary_distance_rel instanceof Float32Array && q.boundary_distance_rel.length === 6 * 25 && q.max_distance_rel < 1e-6,
          `identity boundary lies on the cube mesh (max distance ${q.max_distance_rel})`);
  }
  // A spline folded by swapping two control point layers along u: folded points are reported, and
  // the histogram's negative bins hold them.
  const swapped = functions.map((f) => ({ ...f, point: [...f.point] }));
  for (const f of swapped) if (f.knots[0][2] === 0.5) f.point[0] = 0.02; else if (f.knots[0][2] === 0) f.point[0] = 0.6;
  const folded = vs.splineQuality(text(JSON.stringify({ format: 'volspline-tspline', version: 1, form: 'semi-standard', dimension: 3, domain_min: [0, 0, 0], domain_max: [1, 1, 1], functions: swapped })), null, '', { lattice: 8, bins: 4 });
  const negative = folded.ok ? folded.counts[0] + folded.counts[1] : -1;
  check(folded.ok && folded.min_scaled_jacobian < 0 && folded.folded.length > 0 && folded.boundary_distance_rel === null,
        `a folded spline reports its folded points (${folded.ok ? folded.folded.length / 3 : folded.message})`);
  check(folded.ok && negative >= folded.folded.length / 3, `the histogram's bins below 0 hold the folded points (${negative})`);
  const bad = vs.splineQuality(text('{"format":"x"}'), null, '', {});
  check(bad.ok === false && /spline JSON/.test(bad.message), `bad JSON gives a message: ${bad.message}`);
  const badOption = vs.splineQuality(json, null, '', { lattice: 1 });
  check(badOption.ok === false && /lattice/.test(badOption.message), `a lattice of 1 is refused: ${badOption.message}`);
};
