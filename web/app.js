// SPDX-License-Identifier: MIT
// The page: tabs, the core's start, the samples menus. Each tab lives in tabs/*_tab.js, the
// shared UI in ui.js; the core runs in the worker, and this code never sees a C++ type, only
// {ok, ...} objects and typed arrays.
import { $, jobs, setProgress, showError, samplesMenu } from './ui.js';
import { meshTab } from './tabs/mesh_tab.js';
import { gpcRun } from './tabs/gpc_run.js';
import { volumeTab } from './tabs/volume_tab.js';
import { lensTab } from './tabs/lens_tab.js';

jobs.ready().then(({ version, jobs: available }) => {
  $('core-version').textContent = 'core ' + version;
  setProgress('ready', 0);
  jobs.available = available;
  meshTab.updateButtons();
  if (available.includes('vol2spline')) for (const id of ['volume-run', 'volume-download-json', 'volume-options']) $(id).hidden = false;
}, (e) => { setProgress('core failed to load', 0); showError(e.message); });

const tabs = ['mesh', 'lens', 'volume'];
function selectTab(name) {
  for (const t of tabs) {
    $('tab-' + t).setAttribute('aria-selected', String(t === name));
    $('tab-' + t).tabIndex = t === name ? 0 : -1;
    $('panel-' + t).hidden = t !== name;
  }
  if (name === 'mesh') meshTab.view?.requestDraw();
  if (location.hash !== '#' + name) history.replaceState(null, '', '#' + name);
}
for (const t of tabs) $('tab-' + t).addEventListener('click', () => selectTab(t));
// Arrow keys, Home and End move between the tabs (WAI-ARIA tabs pattern: one tab in the tab order).
$('tab-mesh').parentElement.addEventListener('keydown', (e) => {
  const i = tabs.findIndex((t) => $('tab-' + t) === e.target);
  if (i < 0) return;
  const next = { ArrowRight: i + 1, ArrowLeft: i - 1, Home: 0, End: tabs.length - 1 }[e.key];
  if (next === undefined) return;
  e.preventDefault();
  const t = tabs[(next + tabs.length) % tabs.length];
  selectTab(t);
  $('tab-' + t).focus();
});

fetch('samples/index.json').then((r) => (r.ok ? r.json() : [])).then((list) => {
  samplesMenu($('mesh-samples'), 'meshes', list, (b, n) => meshTab.open(b, n));
  samplesMenu($('lens-samples'), 'images', list, (b, n) => lensTab.open(b, n));
  samplesMenu($('volume-samples'), 'volumes', list, (b, n) => volumeTab.open(b, n));
  $('volume-samples').hidden = !list.some((s) => s.kind === 'volumes');
}).catch(() => {});
selectTab(tabs.includes(location.hash.slice(1)) ? location.hash.slice(1) : 'mesh');

// Hooks for the end-to-end tests and the console (read-only use).
window.volspline = { jobs, meshTab, gpcRun, lensTab, volumeTab, showError };
