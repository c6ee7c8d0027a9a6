// One run's page: status, stage, progress and ETA at the top, a live readout of the
// current state (ea, q, p', ev; the creep stage's time and deformation), then plots that
// grow as the server-sent events of /runs/{id}/events arrive. The stream replays the
// history to a late client, so a finished run is drawn the same way as a live one.
// Finished runs and uploaded lab readings can be overlaid on the plots while the run goes.
// The shear curves start at the consolidated state (εa 0, q 0, εv 0; p' = σ3), the state
// the first streamed reading departs from. Once done: the run's Mohr circle at failure
// and its envelope (GET /runs/{id}/envelope), the envelope's line in p'-q, and a printable
// report (print_report.js).

import { el, getAll, getJSON, postJSON, progressElement, axisLabel } from './api.js';
import { Chart } from './chart.js';
import { SpecimenView } from './specimen_view.js';
import { envelopeTable, envelopeText, mohrChart } from './envelope.js';
import { printButton, printHeader } from './print_report.js';

const ENERGY_KEYS = ['strain_J', 'slip_J', 'damping_J', 'kinetic_J', 'bond_J', 'boundary_work_J', 'creep_J', 'breakage_J'];
const MEASURE_KEYS = ['z_displacement_mm', 'porosity', 'coordination', 'rotation_rate_x_rad_s', 'rotation_rate_y_rad_s', 'rotation_rate_z_rad_s'];
const SERIES_CSV = [
  ['stress-strain', 'q, p, σ1, σ3 vs axial strain'], ['volumetric', 'volumetric strain'],
  ['creep', 'creep, all stages'], ['energies', 'energies'], ['measurements', 'measurement spheres'],
];
const fmt = (v, d = 3) => (v == null || !Number.isFinite(Number(v)) ? '—' : Number(v).toFixed(d));
const col = (columns, name) => columns.indexOf(name);
// Binary floating-point noise off (8.899999999999999 -> 8.9) for display.
const tidy = v => (typeof v === 'number' ? Number(v.toPrecision(10)) : v);

export class RunView {
  constructor(container, runId) {
    this.container = container;
    this.id = runId;
    this.source = null;
    this.measurements = []; // raw measurement events, re-plotted when the quantity changes
    this.stageLevels = {};  // creep stage -> stress level, from the `stage` events
    this.creepStart = {};   // creep stage -> {t, dBefore}: its origin (coordinate translation)
    this.lastCreep = null;  // the last raw creep reading (deformation before the next stage's load)
    this.scheme = null;
    this.build();
    this.refreshStatus();
    this.connect();
  }

  conditions() {
    const s = this.scheme, r = this.run || {};
    const parts = [`run #${this.id}${r.name ? ' ' + r.name : ''}`];
    if (s) {
      parts.push(`σ3 = ${tidy(s.loading?.confining_pressure_kPa)} kPa`);
      if (s.specimen) parts.push(`w = ${tidy(s.specimen.moisture_content_pct)} %`, `specimen ${tidy(s.specimen.diameter_mm)} × ${tidy(s.specimen.height_mm)} mm`);
      if (s.loading?.stress_levels) parts.push(`S = ${s.loading.stress_levels.join('/')}`);
    }
    return parts.join(' · ');
  }

  build() {
    const id = this.id;
    this.header = el('div', { class: 'run-header' });
    this.readout = el('div', { class: 'readout', id: 'live-readout', 'aria-live': 'polite', role: 'status' }, 'waiting for the first reading…');
    this.eventsInfo = el('span', { class: 'events-info' }, 'connecting…');
    const csvLinks = el('span', { class: 'csv-links' }, 'Server CSV: ',
      SERIES_CSV.map(([s, title]) => el('a', { href: `/runs/${id}/results/${s}?format=csv`, download: `run${id}_${s}.csv`, title }, s)));
    this.overlayRun = el('select', { id: 'overlay-run', 'aria-label': 'finished run to overlay' });
    this.overlaySet = el('select', { id: 'overlay-dataset', 'aria-label': 'lab dataset to overlay' });
    this.overlayInfo = el('span', { class: 'hint', id: 'overlay-info' });
    const overlay = el('div', { class: 'row overlay-bar print-hide' },
      el('label', {}, 'overlay run ', this.overlayRun),
      el('button', { type: 'button', id: 'overlay-run-add', onclick: () => this.addRunOverlay(Number(this.overlayRun.value)) }, 'add'),
      el('label', {}, 'lab readings ', this.overlaySet),
      el('button', { type: 'button', id: 'overlay-dataset-add', onclick: () => this.addDatasetOverlay(Number(this.overlaySet.value)) }, 'add'),
      el('button', { type: 'button', id: 'overlay-clear', onclick: () => this.clearOverlays() }, 'clear overlays'),
      this.overlayInfo);
    this.summaryBox = el('div', { class: 'summary' });
    this.envelopeBox = el('section', { class: 'card', id: 'run-envelope' });
    this.specimenBox = el('section', { class: 'card print-hide', id: 'specimen-card' });
    this.printHead = el('div');
    const grid = el('div', { class: 'plot-grid' });
    this.container.replaceChildren(
      this.printHead,
      el('h2', {}, `Run ${id}`), this.header, this.readout,
      el('p', { class: 'toolbar print-hide' }, this.eventsInfo, ' ', csvLinks, ' ', printButton('run-print')),
      overlay,
      el('p', { class: 'hint plot-help' }, 'Plots: hover for values, drag a box to zoom, wheel to zoom time, shift-drag to pan, double-click or "reset" to see all; click a legend entry to hide or show it.'),
      grid, this.envelopeBox, this.specimenBox, this.summaryBox);
    const cond = () => this.conditions();
    const mk = o => new Chart(grid, { conditions: cond, ...o });
    this.qPlot = mk({ id: 'plot-q', title: 'Deviator stress vs axial strain', xLabel: 'axial strain (%)', yLabel: 'q (kPa)', yFromZero: true, fileName: `run${id}_q` });
    this.vPlot = mk({ id: 'plot-vol', title: 'Volumetric vs axial strain (contraction +)', xLabel: 'axial strain (%)', yLabel: 'volumetric strain (%)', fileName: `run${id}_volumetric` });
    this.pqPlot = mk({ id: 'plot-pq', title: "Stress path q vs p'", xLabel: "p' (kPa)", yLabel: 'q (kPa)', yFromZero: true, fileName: `run${id}_stress_path` });
    // Creep on linear and on log time: the linear plot shows the instant deformation and
    // the steady rate, the log plot the primary (log-time) part. Each stage from its own
    // origin (coordinate translation, as GET /runs/{id}/results/creep?stage=k): time from
    // its load step, deformation from the level before it; the log axis leaves out t = 0.
    this.creepPlot = mk({ id: 'plot-creep', title: 'Creep per stage, linear time (each stage from t = 0)', xLabel: 'time since stage start (min)', yLabel: 'deformation since stage load (mm)', xLogAllowed: true, yFromZero: true, fileName: `run${id}_creep` });
    this.creepLogPlot = mk({ id: 'plot-creep-log', title: 'Creep per stage, log time (each stage from t = 0)', xLabel: 'time since stage start (min, log)', yLabel: 'deformation since stage load (mm)', xLog: true, xLogAllowed: true, yFromZero: true, fileName: `run${id}_creep_log` });
    // The whole creep test on one time axis: stage 2 follows stage 1 (raw readings, time and
    // deformation since creep began, as GET /runs/{id}/results/creep_raw).
    this.creepTimeline = mk({ id: 'plot-creep-timeline', title: 'Creep, whole test (stages one after another)', xLabel: 'time since creep began (min)', yLabel: 'deformation since creep began (mm)', xLogAllowed: true, yFromZero: true, fileName: `run${id}_creep_timeline` });
    this.energyPlot = mk({ id: 'plot-energy', title: 'Energies', xLabel: 'mechanical step (cumulative over phases)', yLabel: 'energy (J)', fileName: `run${id}_energies` });
    this.measurePlot = mk({ id: 'plot-measure', title: 'Measurement spheres', xLabel: 'mechanical step', yLabel: axisLabel(MEASURE_KEYS[0]), fileName: `run${id}_measurements` });
    this.measureKey = MEASURE_KEYS[0];
    const pick = el('select', { class: 'measure-quantity', 'aria-label': 'measured quantity' }, MEASURE_KEYS.map(k => el('option', { value: k }, axisLabel(k))));
    pick.addEventListener('change', () => { this.measureKey = pick.value; this.replotMeasurements(); });
    this.measurePlot.tools.prepend(pick);
    this.plots = [this.qPlot, this.vPlot, this.pqPlot, this.creepPlot, this.creepLogPlot, this.creepTimeline, this.energyPlot, this.measurePlot];
    this.loadOverlayLists();
  }

  async loadOverlayLists() {
    try {
      const [runs, sets] = await Promise.all([getAll('/runs', 'runs'), getAll('/datasets', 'datasets')]);
      const done = runs.filter(r => r.status === 'done' && r.id !== this.id);
      this.overlayRun.replaceChildren(...(done.length ? done.map(r => el('option', { value: r.id }, `#${r.id} ${r.name || ''}`))
        : [el('option', { value: '' }, 'no other finished run')]));
      this.overlaySet.replaceChildren(...(sets.length ? sets.map(d => el('option', { value: d.id }, `#${d.id} ${d.name || ''}`))
        : [el('option', { value: '' }, 'no dataset uploaded')]));
    } catch (e) { this.overlayInfo.textContent = e.message; }
  }

  async addRunOverlay(rid) {
    if (!rid) return;
    try {
      const [ss, cr] = await Promise.all([getJSON(`/runs/${rid}/results/stress-strain`), getJSON(`/runs/${rid}/results/creep`)]);
      const vol = await getJSON(`/runs/${rid}/results/volumetric`);
      const name = `run #${rid}`;
      const c = ss.columns, ea = col(c, 'axial_strain_pct'), q = col(c, 'q_kPa'), p = col(c, 'p_kPa');
      const dash = [6, 4];
      this.qPlot.setSeries(`${name} q`, ss.rows.map(r => [r[ea], r[q]]), { dash });
      this.pqPlot.setSeries(`${name}`, ss.rows.map(r => [r[p], r[q]]), { dash });
      this.vPlot.setSeries(`${name} εv`, vol.rows.map(r => [r[0], r[1]]), { dash });
      const byStage = {};
      for (const r of cr.rows) (byStage[r[0]] ||= []).push([r[1], r[2]]);
      for (const [k, pts] of Object.entries(byStage)) {
        this.creepPlot.setSeries(`${name} stage ${k}`, pts, { dash });
        this.creepLogPlot.setSeries(`${name} stage ${k}`, pts, { dash });
      }
      this.overlayInfo.textContent = `overlaid ${name}`;
    } catch (e) { this.overlayInfo.textContent = `run #${rid}: ${e.message}`; }
  }

  async addDatasetOverlay(did) {
    if (!did) return;
    try {
      const d = await getJSON(`/datasets/${did}`);
      let n = 0;
      for (const curve of d.data?.curves || []) {
        const c = curve.columns || [];
        const get = (r, k) => (col(c, k) >= 0 && r[col(c, k)] != null ? Number(r[col(c, k)]) : NaN);
        const style = { style: 'points' };
        if (curve.kind === 'shear') {
          const name = `lab #${did}${curve.confining_kPa != null ? ` @${curve.confining_kPa} kPa` : ''}`;
          const q = curve.rows.map(r => [get(r, 'axial_strain_pct'), get(r, 'q_kPa')]);
          this.qPlot.setSeries(`${name} q`, q, style);
          this.pqPlot.setSeries(name, curve.rows.map(r => [Number(curve.confining_kPa) + get(r, 'q_kPa') / 3, get(r, 'q_kPa')]), style);
          this.vPlot.setSeries(`${name} εv`, curve.rows.map(r => [get(r, 'axial_strain_pct'), get(r, 'volumetric_strain_pct')]), style);
          n += curve.rows.length;
        } else if (curve.kind === 'creep') {
          const pts = curve.rows.map(r => [get(r, 'time_min'), get(r, 'axial_deformation_mm')]);
          this.creepPlot.setSeries(`lab #${did} stage ${curve.stage}`, pts, style);
          this.creepLogPlot.setSeries(`lab #${did} stage ${curve.stage}`, pts, style);
          n += curve.rows.length;
        }
      }
      this.overlayInfo.textContent = `overlaid dataset #${did} (${n} readings)`;
      this.overlayInfo.dataset.readings = String(n);
    } catch (e) { this.overlayInfo.textContent = `dataset #${did}: ${e.message}`; }
  }

  clearOverlays() {
    for (const p of this.plots) p.removeSeries(n => /^(run #|lab #)/.test(n));
    this.overlayInfo.textContent = '';
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
      run.error ? el('div', { class: 'error run-error', id: 'run-error' }, `Why it failed: ${run.error}`) : null].filter(x => x != null));
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
      if (!this.scheme && run.scheme_id != null) {
        getJSON(`/schemes/${run.scheme_id}`).then(s => {
          this.scheme = s.scheme;
          this.printHead.replaceChildren(printHeader(`Run #${this.id} ${run.name || ''}`, this.conditions(), this.scheme));
        }).catch(() => {});
      }
      // Once the server says the run is over, the header's activity line is refreshed at once.
      if (!['queued', 'running'].includes(run.status) && !this.activityNotified) {
        this.activityNotified = true;
        window.dispatchEvent(new Event('triax-activity'));
      }
      this.renderHeader(run);
      if (run.status === 'done') { this.loadSummary(); this.loadSpecimen(); this.loadEnvelope(); this.noCreepNote(); }
      this.printHead.replaceChildren(printHeader(`Run #${this.id} ${run.name || ''}`, this.conditions(), this.scheme));
    } catch (e) { this.header.replaceChildren(el('span', { class: 'error' }, e.message)); }
  }

  // The last shear reading (εa, q, p', εv) stays in view; in creep the stage's reading
  // (time and deformation from its origin, and the stage's q) follows it.
  showReadout() {
    const item = ([k, v, u, n]) => el('span', { class: 'readout-item', dataset: { key: k } }, el('b', {}, k), ` ${fmt(v, n)} ${u}`);
    const parts = [];
    const d = this.lastShear;
    if (d) {
      const sigma3 = d.p_kPa != null && d.q_kPa != null ? d.p_kPa - d.q_kPa / 3 : null;
      parts.push(el('div', { class: 'readout-group', id: 'readout-shear' }, el('span', { class: 'readout-phase' }, this.lastCreepReading ? 'shear test (end)' : 'shear'),
        ...[['εa', d.axial_strain_pct, '%', 3], ['q', d.q_kPa, 'kPa', 1], ["p'", d.p_kPa, 'kPa', 1], ['εv', d.volumetric_strain_pct, '%', 3], ['σ3', sigma3, 'kPa', 1]].map(item)));
    }
    const c = this.lastCreepReading;
    if (c) {
      const q = this.stageInfo?.q_target_kPa;
      parts.push(el('div', { class: 'readout-group', id: 'readout-creep' },
        el('span', { class: 'readout-phase' }, `creep stage ${c.stage}${this.stageLevels[c.stage] != null ? ` (S = ${this.stageLevels[c.stage]})` : ''}`),
        // Both changes since this stage's load (the plots' origin); εa total beside them.
        ...[['t', c.t, 'min', 2], ['Δ deformation', c.d, 'mm', 4], ['Δεa', c.dPct, '%', 4], ['εa total', c.pct, '%', 3], ['q', q, 'kPa', 1]].map(item)));
    }
    if (parts.length) this.readout.replaceChildren(...parts);
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
      if (!this.shearStarted) {
        // The consolidated state the shear starts from: εa 0, q 0, εv 0, p' = σ3.
        this.shearStarted = true;
        const sigma3 = d.sigma3_kPa ?? (d.p_kPa - d.q_kPa / 3);
        if (d.axial_strain_pct > 0) {
          this.qPlot.append('q model', 0, 0);
          this.vPlot.append('εv model', 0, 0);
          if (Number.isFinite(sigma3)) this.pqPlot.append('model', sigma3, 0);
        }
      }
      this.qPlot.append('q model', d.axial_strain_pct, d.q_kPa);
      this.vPlot.append('εv model', d.axial_strain_pct, d.volumetric_strain_pct);
      this.pqPlot.append('model', d.p_kPa, d.q_kPa);
      this.lastShear = d;
      this.showReadout();
    });
    // Raw creep readings are cumulative over the stages; each stage is drawn from its own
    // origin: t - t_k (t_k its first reading, right after its load step) and d - d_before
    // (d_before the last reading of the previous stage, 0 before the first stage).
    on('creep', d => {
      const k = d.stage;
      if (!this.creepStart[k]) {
        const prev = this.lastCreep && this.lastCreep.stage < k ? this.lastCreep : null;
        this.creepStart[k] = { t: d.time_min, dBefore: prev ? prev.axial_deformation_mm : 0, pctBefore: prev ? prev.axial_strain_pct : d.axial_strain_pct };
      }
      this.creepOrigin ??= { t: d.time_min };
      const o = this.creepStart[k];
      const t = d.time_min - o.t, dd = d.axial_deformation_mm - o.dBefore;
      this.lastCreep = d;
      const name = `stage ${k}${this.stageLevels[k] != null ? ` (S = ${this.stageLevels[k]})` : ''}`;
      this.creepPlot.append(name, t, dd);
      this.creepLogPlot.append(name, t, dd);
      this.creepTimeline.append(name, d.time_min - this.creepOrigin.t, d.axial_deformation_mm);
      this.lastCreepReading = { stage: k, t, d: dd, pct: d.axial_strain_pct, dPct: d.axial_strain_pct - o.pctBefore };
      this.showReadout();
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
      if (d && d.detail && !this.run?.error) this.header.append(el('div', { class: 'error run-error' }, `Why it failed: ${d.detail}`));
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

  // A run without creep stages (shear only) says so instead of "waiting for data…".
  noCreepNote() {
    const none = !(this.scheme?.loading?.stress_levels?.length) && !Object.keys(this.creepStart).length;
    if (none) for (const p of [this.creepPlot, this.creepLogPlot, this.creepTimeline]) p.setEmptyText('no creep stage in this run (shear only)');
  }

  // The run's Mohr circle at failure and its envelope through the origin (one σ3), and the
  // envelope's line in p'-q (q = M p' + k) on the stress path.
  async loadEnvelope() {
    if (this.envelope) return;
    try {
      const e = this.envelope = await getJSON(`/runs/${this.id}/envelope`);
      if (e.p_q_line && e.circles?.length) {
        const pMax = Math.max(...e.circles.map(c => c.p_kPa)) * 1.15;
        this.pqPlot.setSeries(`Mohr-Coulomb line (${envelopeText(e).replace(/ \(one σ3.*\)$/, '')})`,
          [[0, e.p_q_line.intercept_kPa], [pMax, e.p_q_line.intercept_kPa + e.p_q_line.slope * pMax]], { color: '#7f8c8d', dash: [8, 3] });
      }
      const grid = el('div', { class: 'plot-grid' });
      this.envelopeBox.replaceChildren(el('h3', {}, 'Strength at failure'), envelopeTable('run-envelope-table', [{ label: `run #${this.id}`, envelope: e }]), grid);
      this.mohr = mohrChart(grid, 'run-mohr', [{ label: `run #${this.id}`, envelope: e }], () => this.conditions());
      this.plots.push(this.mohr);
    } catch (err) { this.envelopeBox.replaceChildren(el('p', { class: 'hint' }, `strength envelope: ${err.message}`)); }
  }

  loadSpecimen() {
    if (this.specimen) return;
    this.specimen = new SpecimenView(this.specimenBox, this.id);
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
      const rows = flat.filter(([, v]) => v != null && typeof v !== 'object')
        .map(([k, v]) => el('tr', {}, el('th', {}, k), el('td', {}, typeof v === 'number' ? Number(v.toPrecision(6)) : String(v))));
      const parts = [el('h3', {}, 'Summary'), el('div', { class: 'table-scroll' }, el('table', { class: 'kv', id: 'run-summary' }, rows))];
      if (Array.isArray(s.creep_stages) && s.creep_stages.length) {
        const cols = Object.keys(s.creep_stages[0]).sort((a, b) => (b === 'stage') - (a === 'stage')); // stage first
        const cell = v => (typeof v === 'number' ? Number(v.toPrecision(5)) : v == null ? '—' : String(v));
        parts.push(el('h3', {}, 'Creep stages'), el('div', { class: 'table-scroll' }, el('table', { class: 'grid' },
          el('tr', {}, cols.map(c => el('th', {}, axisLabel(c)))),
          s.creep_stages.map(r => el('tr', {}, cols.map(c => el('td', {}, cell(r[c]))))))));
      }
      this.summaryBox.replaceChildren(...parts);
    } catch (e) { this.summaryBox.replaceChildren(el('p', { class: 'hint' }, `summary: ${e.message}`)); }
  }

  close() {
    if (this.source) this.source.close();
    if (this.specimen) this.specimen.close();
    for (const p of this.plots) p.destroy();
  }
}
