// SPDX-License-Identifier: MIT
// The Mesh tab's "GPC domain" run: the gpc job on the open mesh (any genus), its surface
// coloured by cuboid with the poly-edges and corners in the 3D view, its stats, and downloads of
// DOMAIN.json and SEG.glb (the files `volspline gpc -o DOMAIN.json --glb SEG.glb` writes).
import { $, download, fillStats, fmt, baseName } from '../ui.js';
import { meshTab } from './mesh_tab.js';

export const gpcRun = {
  result: null,  // the last gpc result shown

  render(r) {
    this.result = r;
    meshTab.view?.setGpc(r);
    const s = r.stats, i = meshTab.info, t = s.times_s;
    fillStats($('mesh-stats'), [
      ['file', i.file], ['vertices', i.vertices], ['faces', i.faces], ['genus', s.genus],
      ['t_shapes', s.t_shapes], ['tubes', s.tubes], ['caps', s.caps], ['cuboids', s.cuboids],
      ['interfaces', s.interfaces], ['ill_points', s.ill_points], ['flipped_triangles', s.flipped_triangles],
      ['grid_inverted_hexes', s.grid_inverted_hexes], ['grid_min_scaled_jacobian', fmt(s.grid_min_scaled_jacobian, 3)],
      ['interface_gap_rel', fmt(s.interface_gap_rel, 3)], ['grid_nodes', s.grid_nodes], ['surface_vertices', s.surface_vertices],
      ['cut_disc_intersections', s.cut_disc_intersections], ['tightened_cuts', s.tightened_cuts],
      ...('limb_caps' in s ? [['limb_caps', s.limb_caps]] : []), ...(s.limb_fallback ? [['limb_fallback', s.limb_fallback]] : []),
      ...['validate', 'decompose', 't_to_cube', 'volumetric_map'].filter((k) => k in t).map((k) => [`time_${k}_s`, fmt(t[k], 3)]),
      ['time_s', fmt(t.total, 3)], ['worker_ms', fmt(r.ms_worker, 4)],
    ]);
    for (const k of ['domain', 'seg', 'stats']) $('mesh-download-' + k).disabled = false;
  },

  reset() {
    this.result = null;
    for (const k of ['domain', 'seg']) $('mesh-download-' + k).disabled = true;
  },
};

meshTab.addRun({
  button: $('mesh-run-gpc'), job: 'gpc', options: () => ({}),
  render: (r) => gpcRun.render(r), reset: () => gpcRun.reset(),
});
$('mesh-download-domain').addEventListener('click', () => download(gpcRun.result.domain_json, baseName(meshTab.name) + '.domain.json', 'application/json'));
$('mesh-download-seg').addEventListener('click', () => download(gpcRun.result.glb, baseName(meshTab.name) + '.seg.glb', 'model/gltf-binary'));
