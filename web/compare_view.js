// Lab readings against a run: upload a dataset (POST /datasets), pick a finished run and
// a dataset, and show what POST /comparisons returns: the metrics table, the overlay of
// model and lab for one curve, and its residual. The overlay draws the whole lab curve
// (GET /datasets/{id}) and the whole model curve (GET /runs/{id}/results/...), not only
// the compared points: readings outside the model's range are drawn apart and counted.
// Downloads: the residual table as CSV, each plot as PNG/CSV.
// A run has one σ3: the service compares it with the dataset's curves at that σ3 (or at
// the σ3 picked here) and labels every row with its lab curve's sigma3_kPa; the page
// labels every row, series and picker entry with it. The strength envelope of the dataset
// and of the run (GET /datasets/{id}/envelope, GET /runs/{id}/envelope) is drawn below.

import { el, getAll, getJSON, moreButton, PAGE, postJSON, postRaw, del, ProblemError, axisLabel } from './api.js';
import { Chart, downloadBlob } from './chart.js';
import { drawMohr, drawPq, envelopeTable, kpaText, mohrChart, pqChart } from './envelope.js';
import { printButton, printHeader } from './print_report.js';

const CONTENT_TYPES = { json: 'application/json', csv: 'text/csv', gds: 'text/csv', ags: 'text/plain' };

function guessFormat(fileName) {
  const ext = (fileName.split('.').pop() || '').toLowerCase();
  if (ext === 'json') return 'json';
  if (ext === 'ags') return 'ags';
  return '';
}

// What the model-vs-lab y axis shows for each compared curve.
const CURVE_NAMES = { stress_strain: 'q', volumetric: 'volumetric strain', creep: 'axial deformation' };

// The compared curve in a lab engineer's words, with its σ3.
const CURVE_WORDS = { stress_strain: 'q vs εa', volumetric: 'εv vs εa', creep: 'creep' };
const curveLabel = c => `σ3 ${kpaText(c.sigma3_kPa)} · ${CURVE_WORDS[c.curve] || c.curve}${c.stage != null ? ' stage ' + c.stage : ''}`;
const samePressure = (a, b) => Math.abs(a - b) <= 0.02 * Math.max(Math.abs(a), Math.abs(b));

const num = v => (typeof v === 'number' ? Number(v.toPrecision(5)) : v == null ? '—' : String(v));

export class CompareView {
  constructor(container) {
    this.container = container;
    this.comparison = null;
    this.build();
    this.refreshLists();
  }

  build() {
    this.fileInput = el('input', { type: 'file', id: 'dataset-file', accept: '.csv,.txt,.json,.ags,.gds', 'aria-label': 'lab readings file' });
    this.nameInput = el('input', { type: 'text', id: 'dataset-name', placeholder: 'name (default: file name)', 'aria-label': 'dataset name' });
    this.formatSelect = el('select', { id: 'dataset-format', 'aria-label': 'file format' },
      ['', 'csv', 'gds', 'ags', 'json'].map(f => el('option', { value: f }, f || 'sniff')));
    this.uploadError = el('div', { class: 'field-error', id: 'upload-error', role: 'alert' });
    this.uploadInfo = el('div', { class: 'hint', id: 'upload-info' });
    const upload = el('section', { class: 'card' },
      el('h3', {}, 'Upload lab readings'),
      el('p', { class: 'hint' }, 'Plain CSV with units in the headers (kind, stage, confining_kPa, time_min, axial_strain_pct, axial_deformation_mm, q_kPa, volumetric_strain_pct), a GDS-Lab export, AGS4 (TREG/TRET) or JSON.'),
      el('div', { class: 'row' }, this.fileInput, this.nameInput, el('label', {}, 'format ', this.formatSelect),
        el('button', { type: 'button', id: 'upload-button', onclick: () => this.upload() }, 'Upload')),
      this.uploadError, this.uploadInfo);

    this.datasetTable = el('table', { class: 'grid', id: 'dataset-table' });
    this.datasetScroll = el('div', { class: 'table-scroll' }, this.datasetTable);
    this.datasetMore = el('div', { class: 'row' });
    this.datasetCount = PAGE;
    this.runSelect = el('select', { id: 'compare-run' });
    this.datasetSelect = el('select', { id: 'compare-dataset' });
    this.sigma3Select = el('select', { id: 'compare-sigma3' });
    this.datasetSelect.addEventListener('change', () => this.fillSigma3());
    this.compareError = el('div', { class: 'field-error', id: 'comparison-error', role: 'alert' });
    const pick = el('section', { class: 'card print-hide' },
      el('h3', {}, 'Compare a finished run with a dataset'),
      el('div', { class: 'row' }, el('label', {}, 'run ', this.runSelect), el('label', {}, 'dataset ', this.datasetSelect),
        el('label', {}, 'lab σ3 ', this.sigma3Select),
        el('button', { type: 'button', id: 'compare-button', onclick: () => this.compare() }, 'Compare'),
        el('button', { type: 'button', onclick: () => this.refreshLists() }, 'Refresh lists')),
      this.compareError);

    this.metrics = el('div', { id: 'comparison-metrics' });
    this.curveSelect = el('select', { id: 'comparison-curve' });
    this.curveSelect.addEventListener('change', () => this.showCurve());
    const grid = el('div', { class: 'plot-grid' });
    this.printHead = el('div');
    this.envelopeBox = el('div', { id: 'comparison-envelope' });
    const envelopeGrid = el('div', { class: 'plot-grid' });
    const result = el('section', { class: 'card', id: 'comparison-result' },
      el('h3', {}, 'Comparison'), this.printHead, this.metrics,
      el('div', { class: 'row' }, el('label', {}, 'curve ', this.curveSelect),
        el('button', { type: 'button', id: 'residual-csv', onclick: () => this.downloadResiduals() }, 'Download residuals CSV'),
        printButton('comparison-print')),
      grid, el('h4', {}, 'Strength envelope: lab and run'), this.envelopeBox, envelopeGrid);
    const conditions = () => (this.comparison ? `run #${this.comparison.run_id} (σ3 ${kpaText(this.comparison.run_sigma3_kPa)}) vs dataset #${this.comparison.dataset_id}` : '');
    this.overlay = new Chart(grid, { id: 'plot-overlay', title: 'Model vs lab', xLabel: '', yLabel: '', xLogAllowed: true, fileName: 'overlay', conditions });
    this.residual = new Chart(grid, { id: 'plot-residual', title: 'Residual (model − lab)', xLabel: '', yLabel: '', xLogAllowed: true, fileName: 'residual', conditions });
    this.mohr = mohrChart(envelopeGrid, 'comparison-mohr', [], conditions);
    this.pq = pqChart(envelopeGrid, 'comparison-pq', [], conditions);
    for (const c of [this.mohr, this.pq]) c.setEmptyText('compare a run with a dataset to see both envelopes');
    this.conditions = conditions;

    upload.classList.add('print-hide');
    this.container.replaceChildren(el('h2', { class: 'print-hide' }, 'Lab readings'), upload,
      el('section', { class: 'card print-hide' }, el('h3', {}, 'Datasets'), this.datasetScroll, this.datasetMore), pick, result);
  }

  // Overlapping refreshes (page load, then an upload) must not let the older answer
  // overwrite the newer lists.
  async refreshLists() {
    const seq = this.listSeq = (this.listSeq || 0) + 1;
    try {
      // The pickers offer every run and dataset; the table shows `datasetCount` of them.
      const [runs, datasets] = await Promise.all([getAll('/runs', 'runs'), getAll('/datasets', 'datasets')]);
      if (seq !== this.listSeq) return;
      const total = datasets.length, shown = datasets.slice(0, this.datasetCount);
      const keepRun = this.runSelect.value, keepSet = this.datasetSelect.value;
      // Only finished runs can be compared (the server answers 409 for the others).
      const done = runs.filter(r => r.status === 'done');
      this.runSelect.replaceChildren(...(done.length ? done.map(r => el('option', { value: r.id }, `#${r.id} ${r.name || ''}`))
        : [el('option', { value: '' }, 'no finished run yet')]));
      this.runSelect.value = keepRun && done.some(r => String(r.id) === keepRun) ? keepRun : done.length ? String(done[0].id) : '';
      this.datasetSelect.replaceChildren(...datasets.map(d => el('option', { value: d.id }, `#${d.id} ${d.name || ''}`)));
      if (keepSet && datasets.some(d => String(d.id) === keepSet)) this.datasetSelect.value = keepSet;
      this.datasets = datasets;
      this.fillSigma3();
      this.renderDatasets(shown);
      this.datasetMore.replaceChildren(moreButton('datasets-more', shown.length, total, () => { this.datasetCount += PAGE; this.refreshLists(); }));
    } catch (e) { this.compareError.textContent = e.message; }
  }

  // The σ3 values of the dataset picked: "the run's" (the service matches it) or one of them.
  fillSigma3() {
    const d = (this.datasets || []).find(x => String(x.id) === this.datasetSelect.value);
    const keep = this.sigma3Select.value;
    const set = [];
    for (const c of d?.curves || []) if (c.confining_kPa != null && !set.some(p => samePressure(p, c.confining_kPa))) set.push(c.confining_kPa);
    this.sigma3Select.replaceChildren(el('option', { value: '' }, "the run's σ3"), ...set.map(p => el('option', { value: p }, kpaText(p))));
    if ([...this.sigma3Select.options].some(o => o.value === keep)) this.sigma3Select.value = keep;
  }

  renderDatasets(datasets) {
    const curveText = d => (d.curves || []).map(c => `${c.kind}${c.stage != null ? ' ' + c.stage : ''} at σ3 ${kpaText(c.confining_kPa)}: ${c.points} pts`).join('; ');
    this.datasetTable.replaceChildren(
      el('tr', {}, ['id', 'name', 'curves (kind, stage, σ3: readings)', ''].map(h => el('th', {}, h))),
      ...datasets.map(d => el('tr', {}, el('td', {}, d.id), el('td', {}, d.name || ''), el('td', {}, curveText(d)),
        el('td', {}, el('button', { type: 'button', 'aria-label': `delete dataset #${d.id} ${d.name || ''}`.trim(), onclick: async () => { await del(`/datasets/${d.id}`); this.refreshLists(); } }, 'delete')))));
  }

  async upload() {
    this.uploadError.textContent = '';
    this.uploadInfo.textContent = '';
    const file = this.fileInput.files[0];
    if (!file) { this.uploadError.textContent = 'choose a file first'; return; }
    const format = this.formatSelect.value || guessFormat(file.name);
    const name = this.nameInput.value.trim() || file.name.replace(/\.[^.]*$/, '');
    const params = new URLSearchParams({ name });
    if (format) params.set('format', format);
    try {
      const text = await file.text();
      const res = await postRaw(`/datasets?${params}`, text, CONTENT_TYPES[format] || 'text/csv');
      // The lists first, then the message: once the message shows, the new dataset can be picked.
      await this.refreshLists();
      this.datasetSelect.value = String(res.id);
      this.uploadInfo.dataset.datasetId = res.id;
      this.uploadInfo.textContent = `dataset #${res.id} "${res.name}": ` +
        (res.curves || []).map(c => `${c.kind}${c.stage != null ? ' ' + c.stage : ''} (${c.points} points)`).join(', ');
    } catch (e) {
      const p = e instanceof ProblemError ? e.problem : {};
      const where = [p.line != null ? `line ${p.line}` : '', p.column != null ? `column ${p.column}` : ''].filter(Boolean).join(', ');
      const said = p.line != null && new RegExp(`line ${p.line}\\b`).test(e.message); // detail may already name it
      this.uploadError.textContent = `${file.name}${where && !said ? ' ' + where : ''}: ${e.message}`;
    }
  }

  async compare() {
    this.compareError.textContent = '';
    const run_id = Number(this.runSelect.value), dataset_id = Number(this.datasetSelect.value);
    if (!run_id || !dataset_id) { this.compareError.textContent = 'pick a run and a dataset'; return; }
    try {
      const body = { run_id, dataset_id };
      if (this.sigma3Select.value) body.sigma3_kPa = Number(this.sigma3Select.value);
      const comparison = await postJSON('/comparisons', body);
      // The whole curves behind the metrics: the run's series and the dataset's readings.
      const [ss, vol, creep, dataset, labEnvelope, runEnvelope, run] = await Promise.all([
        getJSON(`/runs/${run_id}/results/stress-strain`), getJSON(`/runs/${run_id}/results/volumetric`),
        getJSON(`/runs/${run_id}/results/creep`), getJSON(`/datasets/${dataset_id}`),
        getJSON(`/datasets/${dataset_id}/envelope`).catch(() => null), getJSON(`/runs/${run_id}/envelope`).catch(() => null),
        getJSON(`/runs/${run_id}`)]);
      this.model = { ss, vol, creep };
      this.dataset = dataset;
      this.show(comparison);
      const sets = [{ label: `lab #${dataset_id}`, envelope: labEnvelope }, { label: `run #${run_id}`, envelope: runEnvelope, dash: [6, 4] }];
      this.envelopeBox.replaceChildren(envelopeTable('comparison-envelope-table', sets));
      drawMohr(this.mohr, sets);
      drawPq(this.pq, sets);
      const title = `Comparison #${comparison.id}: run #${run_id} ${run.name || ''} vs dataset #${dataset_id} ${dataset.name || ''}`;
      this.printHead.replaceChildren(printHeader(title, this.conditions(), null));
      const scheme = run.scheme_id != null ? (await getJSON(`/schemes/${run.scheme_id}`).catch(() => null))?.scheme : null;
      if (scheme && this.comparison === comparison) this.printHead.replaceChildren(printHeader(title, this.conditions(), scheme));
    } catch (e) { this.compareError.textContent = e.message; }
  }

  show(comparison) {
    this.comparison = comparison;
    const curves = comparison.curves || [];
    // RMSE and max error carry the curve's unit in the cell; NRMSE is relative to the lab
    // range. Lab readings outside the model's range are not compared: `dropped` says how many.
    const withUnit = (c, k) => (typeof c[k] === 'number' ? `${num(c[k])}${c.unit ? ' ' + c.unit : ''}` : num(c[k]));
    const cols = [['σ3 (kPa)', c => num(c.sigma3_kPa)], ['curve', c => c.curve], ['stage', c => num(c.stage)], ['readings compared', c => num(c.n)],
      ['outside the model range (drawn, not compared)', c => num(c.dropped)], ['RMSE', c => withUnit(c, 'rmse')],
      ['NRMSE (of the lab range)', c => num(c.nrmse)], ['R²', c => num(c.r2)], ['max |error|', c => withUnit(c, 'max_error')]];
    const notes = [...(comparison.warnings || []).map(w => `warning: ${w}`),
      ...(comparison.skipped || []).map(k => `not compared: ${k.sigma3_kPa != null ? curveLabel(k) : k.curve + (k.stage != null ? ' stage ' + k.stage : '')}: ${k.reason}`)];
    // replaceChildren would print a null child as the text "null": only nodes go in.
    this.metrics.replaceChildren(...[
      el('p', { class: 'hint', id: 'comparison-match' }, `comparison #${comparison.id}: run #${comparison.run_id} at σ3 ${kpaText(comparison.run_sigma3_kPa)} vs dataset #${comparison.dataset_id}, ` +
        (comparison.lab_sigma3_kPa != null ? `its curves at σ3 ${kpaText(comparison.lab_sigma3_kPa)}` : 'all its curves (none at the run\'s σ3)')),
      el('div', { class: 'table-scroll' }, el('table', { class: 'grid', id: 'metrics-table' },
        el('tr', {}, cols.map(([h]) => el('th', {}, h))),
        curves.map(c => el('tr', {}, cols.map(([, f]) => el('td', {}, f(c))))))),
      notes.length ? el('ul', { class: 'error', id: 'comparison-warnings' }, notes.map(n => el('li', {}, n))) : null].filter(Boolean));
    this.curveSelect.replaceChildren(...curves.map((c, i) => el('option', { value: i }, curveLabel(c))));
    this.showCurve();
  }

  // The model's whole curve for a compared curve, and the dataset's whole lab curve.
  modelCurve(c) {
    const m = this.model || {};
    if (c.curve === 'stress_strain' && m.ss) return m.ss.rows.map(r => [r[0], r[1]]);
    if (c.curve === 'volumetric' && m.vol) return m.vol.rows.map(r => [r[0], r[1]]);
    if (c.curve === 'creep' && m.creep) {
      const yi = m.creep.columns.indexOf(c.y);
      return m.creep.rows.filter(r => r[0] === c.stage).map(r => [r[1], r[yi]]);
    }
    return [];
  }

  labCurve(c) {
    const want = c.curve === 'creep' ? 'creep' : 'shear';
    const out = [];
    for (const lc of this.dataset?.data?.curves || []) {
      if (lc.kind !== want || (want === 'creep' && lc.stage !== c.stage)) continue;
      if (c.sigma3_kPa != null && !samePressure(Number(lc.confining_kPa), c.sigma3_kPa)) continue; // this row's σ3 only
      const xi = lc.columns.indexOf(c.x), yi = lc.columns.indexOf(c.y);
      if (xi < 0 || yi < 0) continue;
      for (const r of lc.rows) if (r[xi] != null && r[yi] != null) out.push([Number(r[xi]), Number(r[yi])]);
    }
    return out;
  }

  showCurve() {
    const c = (this.comparison?.curves || [])[Number(this.curveSelect.value) || 0];
    this.overlay.clear();
    this.residual.clear();
    if (!c) return;
    const rows = c.residual || [];
    const xl = axisLabel(c.x || 'x');
    const yl = `${CURVE_NAMES[c.curve] || c.curve.replace(/_/g, ' ')}${c.unit ? ' (' + c.unit + ')' : ''}`;
    const isTime = /time/.test(c.x || '');
    for (const p of [this.overlay, this.residual]) {
      p.options.xLabel = xl;
      p.options.xLog = isTime && p.logBox.checked;
      p.logBox.parentElement.hidden = !isTime;
    }
    this.overlay.options.yLabel = yl;
    this.overlay.options.yFromZero = c.curve === 'stress_strain';
    this.residual.options.yLabel = `residual ${c.unit ? '(' + c.unit + ')' : ''}`;
    const model = this.modelCurve(c);
    const lab = this.labCurve(c);
    // Inside the model's x range the reading was compared; outside it is drawn apart.
    const xs = model.map(p => p[0]);
    const lo = Math.min(...xs), hi = Math.max(...xs);
    const inside = lab.filter(([x]) => x >= lo && x <= hi), outside = lab.filter(([x]) => x < lo || x > hi);
    const at = kpaText(c.sigma3_kPa);
    this.overlay.setTitle(`Model vs lab: ${curveLabel(c)}`);
    this.residual.setTitle(`Residual (model − lab): ${curveLabel(c)}`);
    this.overlay.setSeries(`model (run at σ3 ${kpaText(this.comparison.run_sigma3_kPa)})`, model.length ? model : rows.map(r => [r[0], r[1]]));
    this.overlay.setSeries(`lab σ3 ${at}`, inside.length || !rows.length ? inside : rows.map(r => [r[0], r[2]]), { style: 'points', color: '#c0392b' });
    if (outside.length) this.overlay.setSeries(`lab σ3 ${at} outside the model range (${outside.length})`, outside, { style: 'points', color: '#d68910' });
    this.outsideCount = outside.length;
    this.overlay.root.dataset.outside = String(outside.length);
    this.overlay.root.dataset.lab = String(lab.length);
    this.overlay.root.dataset.model = String(model.length);
    this.residual.setSeries(`model − lab σ3 ${at}`, rows.map(r => [r[0], r[3]]), { style: 'points' });
    this.residual.setSeries('zero', rows.length ? [[rows[0][0], 0], [rows[rows.length - 1][0], 0]] : [], { color: '#999', dash: [4, 4] });
  }

  downloadResiduals() {
    if (!this.comparison) return;
    const lines = ['sigma3_kPa,curve,stage,x_name,x,model,lab,residual,unit'];
    for (const c of this.comparison.curves || []) {
      for (const r of c.residual || []) lines.push([c.sigma3_kPa ?? '', c.curve, c.stage ?? '', c.x, r[0], r[1], r[2], r[3], c.unit || ''].join(','));
    }
    downloadBlob(new Blob([lines.join('\n') + '\n'], { type: 'text/csv' }), `comparison${this.comparison.id}_residuals.csv`);
  }
}
