// One run's page: status, stage, progress and ETA at the top, then plots that grow as
// the server-sent events of /runs/{id}/events arrive. The stream replays the history
// to a late client, so a finished run is drawn the same way as a live one.

import { el, getJSON, postJSON, progressElement, axisLabel } from './api.js';
import { Plot } from './plot.js';

const ENERGY_KEYS = ['strain_J', 'slip_J', 'damping_J', 'kinetic_J', 'bond_J', 'boundary_work_J', 'creep_J', 'breakage_J'];
const MEASURE_KEYS = ['z_displacement_mm', 'porosity', 'coordination', 'rotation_rate_x_rad_s', 'rotation_rate_y_rad_s', 'rotation_rate_z_rad_s'];
const SERIES_CSV = [
  ['stress-strain', 'q, p, σ1, σ3 vs axial strain'], ['volumetric', 'volumetric strain'],
  ['creep', 'creep, all stages'], ['energies', 'energies'], ['measurements', 'measurement spheres'],
];

export class RunView {
  constructor(container, runId, onLeave) {
    this.container = container;
    this.id = runId;
    this.onLeave = onLeave;
    this.source = null;
    this.measurements = []; // raw measurement events, re-plotted when the quantity changes
    this.stageLevels = {};  // creep stage -> stress level, from the `stage` events
    this.build();
    this.refreshStatus();
    this.connect();
  }

  build() {
    const id = this.id;
    this.header = el('div', { class: 'run-header' });
    this.eventsInfo = el('span', { class: 'events-info' }, 'connecting…');
    const csvLinks = el('span', { class: 'csv-links' }, 'Server CSV: ',
      SERIES_CSV.map(([s, title]) => el('a', { href: `/runs/${id}/results/${s}?format=csv`, download: `run${id}_${s}.csv`, title }, s)));
    this.summaryBox = el('div', { class: 'summary' });
    const grid = el('div', { class: 'plot-grid' });
    this.container.replaceChildren(
      el('h2', {}, `Run ${id}`), this.header,
      el('p', { class: 'toolbar' }, this.eventsInfo, ' ', csvLinks),
      grid, this.summaryBox);
    this.qPlot = new Plot(grid, { id: 'plot-q', title: 'Deviator stress vs axial strain', xLabel: 'axial strain (%)', yLabel: 'q (kPa)', fileName: `run${id}_q` });
    this.vPlot = new Plot(grid, { id: 'plot-vol', title: 'Volumetric vs axial strain (contraction +)', xLabel: 'axial strain (%)', yLabel: 'volumetric strain (%)', fileName: `run${id}_volumetric` });
    // Creep on linear and on log time side by side: the linear plot shows the instant
    // deformation and the steady rate, the log plot the primary (log-time) part. Time is
    // from the start of each stage (coordinate-translated); the log axis leaves out t = 0.
    this.creepPlot = new Plot(grid, { id: 'plot-creep', title: 'Creep per stage, linear time (from stage start)', xLabel: 'time since stage start (min)', yLabel: 'axial deformation (mm)', xLogAllowed: true, fileName: `run${id}_creep` });
    this.creepLogPlot = new Plot(grid, { id: 'plot-creep-log', title: 'Creep per stage, log time (from stage start)', xLabel: 'time since stage start (min, log)', yLabel: 'axial deformation (mm)', xLog: true, xLogAllowed: true, fileName: `run${id}_creep_log` });
    this.energyPlot = new Plot(grid, { id: 'plot-energy', title: 'Energies', xLabel: 'mechanical step (cumulative over phases)', yLabel: 'energy (J)', fileName: `run${id}_energies` });
    this.measurePlot = new Plot(grid, { id: 'plot-measure', title: 'Measurement spheres', xLabel: 'mechanical step', yLabel: axisLabel(MEASURE_KEYS[0]), fileName: `run${id}_measurements` });
    this.measureKey = MEASURE_KEYS[0];
    const pick = el('select', { class: 'measure-quantity' }, MEASURE_KEYS.map(k => el('option', { value: k }, axisLabel(k))));
    pick.addEventListener('change', () => { this.measureKey = pick.value; this.replotMeasurements(); });
    this.measurePlot.root.querySelector('.plot-tools').prepend(pick);
  }

  renderHeader(run) {
    this.run = run;
    const active = run.status === 'queued' || run.status === 'running';
    this.header.replaceChildren(...[
      el('span', { class: `status status-${run.status}`, id: 'run-status' }, run.status),
      ' ', el('span', { class: 'run-name' }, run.name || ''), ' ',
      progressElement(run.stage, run.progress_pct, run.eta_s), ' ',
      active ? el('button', { type: 'button', onclick: () => postJSON(`/runs/${this.id}/cancel`).then(() => this.refreshStatus()) }, 'Cancel') : null,
      !active ? el('button', { type: 'button', onclick: async () => { const r = await postJSON(`/runs/${this.id}/rerun`); location.hash = `#/runs/${r.id}`; } }, 'Re-run') : null,
      this.stageText(),
      run.error ? el('span', { class: 'error' }, ` ${run.error}`) : null].filter(x => x != null));
  }

  // The creep stage's load, as the `stage` event announces it.
  stageText() {
    const d = this.stageInfo;
    if (!d || d.stress_level == null) return null;
    const parts = [`stage ${d.stage}`, `stress level ${d.stress_level}`];
    if (d.q_target_kPa != null) parts.push(`q target ${Number(d.q_target_kPa).toFixed(1)} kPa`);
    return el('span', { class: 'hint', id: 'stage-info' }, parts.join(' · '));
  }

  async refreshStatus() {
    const seq = this.statusSeq = (this.statusSeq || 0) + 1; // an older answer must not undo a newer one
    try {
      const run = await getJSON(`/runs/${this.id}`);
      if (seq !== this.statusSeq) return;
      // Once the server says the run is over, the header's activity line is refreshed at once.
      if (!['queued', 'running'].includes(run.status) && !this.activityNotified) {
        this.activityNotified = true;
        window.dispatchEvent(new Event('triax-activity'));
      }
      this.renderHeader(run);
      if (run.status === 'done') this.loadSummary();
    } catch (e) { this.header.replaceChildren(el('span', { class: 'error' }, e.message)); }
  }

  connect() {
    let count = 0;
    const src = new EventSource(`/runs/${this.id}/events`);
    this.source = src;
    const on = (type, fn) => src.addEventListener(type, ev => {
      let data;
      try { data = JSON.parse(ev.data); } catch { return; } // transport errors carry no data
      count++;
      this.eventsInfo.textContent = `${count} events received`;
      this.eventsInfo.dataset.count = String(count);
      fn(data);
    });
    on('status', d => { if (this.run) this.renderHeader(Object.assign({}, this.run, d)); });
    on('progress', d => { if (this.run) this.renderHeader(Object.assign({}, this.run, { status: 'running' }, d)); });
    on('stage', d => {
      this.stageInfo = d;
      if (d.stress_level != null) this.stageLevels[d.index] = d.stress_level; // index = creep stage number
      if (this.run) this.renderHeader(Object.assign({}, this.run, { stage: d.stage }));
    });
    on('shear', d => {
      this.qPlot.append('q model', d.axial_strain_pct, d.q_kPa);
      this.vPlot.append('εv model', d.axial_strain_pct, d.volumetric_strain_pct);
    });
    on('creep', d => {
      const name = `stage ${d.stage}${this.stageLevels[d.stage] != null ? ` (S = ${this.stageLevels[d.stage]})` : ''}`;
      this.creepPlot.append(name, d.time_min, d.axial_deformation_mm);
      this.creepLogPlot.append(name, d.time_min, d.axial_deformation_mm);
    });
    // Step counters may restart with each phase; keep the x axis cumulative.
    let stepOffset = 0, lastStep = -Infinity;
    on('energy', d => {
      let step = Number(d.step);
      if (step + stepOffset < lastStep) stepOffset = lastStep;
      step += stepOffset; lastStep = step;
      for (const k of ENERGY_KEYS) if (d[k] != null) this.energyPlot.append(k.replace(/_J$/, ''), step, Number(d[k]));
    });
    on('measurement', d => { this.measurements.push(d); this.plotMeasurement(d); });
    const finish = d => {
      src.close();
      this.eventsInfo.textContent += ' · stream closed';
      this.refreshStatus();
      if (d && d.detail) this.header.append(el('span', { class: 'error' }, ` ${d.detail}`));
    };
    on('done', finish);
    on('error', finish);
    // Transport errors (not the server's `error` event): EventSource reconnects by itself
    // and sends Last-Event-ID, so only a closed stream needs a status refresh.
    src.onerror = () => { if (src.readyState === EventSource.CLOSED) this.refreshStatus(); };
  }

  plotMeasurement(d) {
    if (d[this.measureKey] != null) this.measurePlot.append(`sphere ${d.sphere}`, Number(d.step), Number(d[this.measureKey]));
  }

  replotMeasurements() {
    this.measurePlot.clear();
    this.measurePlot.options.yLabel = axisLabel(this.measureKey);
    for (const d of this.measurements) this.plotMeasurement(d);
  }

  async loadSummary() {
    try {
      const s = await getJSON(`/runs/${this.id}/results/summary`);
      // Scalars, and one level of nested objects (e.g. consolidation) as "group · field".
      const flat = [];
      for (const [k, v] of Object.entries(s)) {
        if (v && typeof v === 'object' && !Array.isArray(v)) for (const [k2, v2] of Object.entries(v)) flat.push([`${axisLabel(k)} · ${axisLabel(k2)}`, v2]);
        else if (!Array.isArray(v)) flat.push([axisLabel(k), v]);
      }
      const rows = flat.filter(([, v]) => v == null || typeof v !== 'object')
        .map(([k, v]) => el('tr', {}, el('th', {}, k), el('td', {}, typeof v === 'number' ? Number(v.toPrecision(6)) : String(v))));
      const parts = [el('h3', {}, 'Summary'), el('table', { class: 'kv', id: 'run-summary' }, rows)];
      if (Array.isArray(s.creep_stages) && s.creep_stages.length) {
        const cols = Object.keys(s.creep_stages[0]).sort((a, b) => (b === 'stage') - (a === 'stage')); // stage first
        parts.push(el('h3', {}, 'Creep stages'), el('table', { class: 'grid' },
          el('tr', {}, cols.map(c => el('th', {}, axisLabel(c)))),
          s.creep_stages.map(r => el('tr', {}, cols.map(c => el('td', {}, typeof r[c] === 'number' ? Number(r[c].toPrecision(5)) : String(r[c])))))));
      }
      this.summaryBox.replaceChildren(...parts);
    } catch (e) { this.summaryBox.replaceChildren(el('p', { class: 'hint' }, `summary: ${e.message}`)); }
  }

  close() { if (this.source) this.source.close(); }
}
