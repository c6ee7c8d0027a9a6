// Closing the loop: ask the service which test effect (seating error, membrane
// compliance, ...) best explains the misfit between a scheme and a dataset, and show the
// report: chosen effect, fitted parameters, error before/after, delta-BIC, verdict.
// Progress comes from the SSE stream /diagnoses/{id}/events (progress, candidate, done,
// error), with polling of GET /diagnoses/{id} as the fallback that also fetches the
// final report.

import { el, getAll, getJSON, postJSON, progressElement } from './api.js';

// Five significant digits; very large or small magnitudes (e.g. moduli in Pa) as 1.2e+8.
const sig = v => (v !== 0 && (Math.abs(v) >= 1e6 || Math.abs(v) < 1e-4) ? v.toExponential(4).replace(/\.?0+e/, 'e') : Number(v.toPrecision(5)));
const num = v => (typeof v === 'number' ? sig(v) : v == null ? '—' : typeof v === 'boolean' ? (v ? 'yes' : 'no') : String(v));

function table(id, cols, rows, headers = cols) {
  return el('table', { class: 'grid', id },
    el('tr', {}, headers.map(h => el('th', {}, h))),
    rows.map(r => el('tr', {}, cols.map(c => el('td', {}, typeof c === 'function' ? c(r) : num(r[c]))))));
}

const paramText = ps => (ps || []).map(p => `${p.name} = ${num(p.value)}${p.unit ? ' ' + p.unit : ''}${p.std != null ? ' ± ' + num(p.std) : ''}`).join('; ');
const ACTIVE = new Set(['queued', 'running']);

// The request limits of POST /datasets/{id}/diagnose, as the server validates them
// (diagnose_options_from_json in server/io/diagnosis_json.cpp; GET /openapi.json does not
// carry them). The browser test sends values just outside them and expects the 422.
export const LIMITS = { budget_runs: [4, 400], max_particles: [0, 1000000], seed: [0, 2 ** 53] };

export class DiagnosisView {
  constructor(container) {
    this.container = container;
    this.timer = null;
    this.source = null;
    this.diagnosisId = null;
    this.build();
    this.refreshLists();
  }

  build() {
    this.datasetSelect = el('select', { id: 'diagnose-dataset' });
    this.runSelect = el('select', { id: 'diagnose-run' });
    this.fields = {};
    const field = (key, label, unit, value, title) => {
      const [min, max] = LIMITS[key];
      const input = el('input', { type: 'number', id: `diagnose-${key.replace(/_/g, '-')}`, value, min, max, step: 1, title });
      const error = el('span', { class: 'field-error', id: `diagnose-${key.replace(/_/g, '-')}-error`, role: 'alert' });
      this.fields[key] = { input, error };
      return el('label', { class: 'diagnose-option' }, `${label}${unit ? ' (' + unit + ')' : ''} `, input,
        el('span', { class: 'limits' }, ` ${min}…${max === 2 ** 53 ? '2⁵³' : max}`), error);
    };
    this.error = el('div', { class: 'field-error', id: 'diagnose-error', role: 'alert' });
    this.progress = el('div', { id: 'diagnosis-progress' }, el('span', { class: 'hint' }, 'no diagnosis selected'));
    this.candidates = el('div', { id: 'diagnosis-candidates' });
    this.report = el('div', { id: 'diagnosis-report' });
    this.list = el('div', { id: 'diagnosis-list' });
    this.container.replaceChildren(
      el('h2', {}, 'Diagnosis'),
      el('section', { class: 'card' },
        el('p', { class: 'hint' }, 'Calibrates the base model to the dataset, then ranks the candidate effects (rolling resistance, grain breakage, seating error, membrane compliance, ...) by their residual signature, fits the best ones as augmented models and keeps one only if it lowers BIC (with an effective number of readings). The scheme is taken from the chosen run. The budget bounds the calibration runs; each candidate costs further DEM runs.'),
        el('div', { class: 'row' },
          el('label', {}, 'dataset ', this.datasetSelect), el('label', {}, 'scheme of run ', this.runSelect),
          field('budget_runs', 'calibration budget', 'DEM runs', 24),
          field('max_particles', 'max particles per run', '', 0, '0 = as in the scheme'),
          field('seed', 'seed', '', 1),
          el('button', { type: 'button', id: 'diagnose-button', onclick: () => this.start() }, 'Diagnose')),
        this.error),
      el('section', { class: 'card' }, el('h3', {}, 'Progress'), this.progress, this.candidates),
      el('section', { class: 'card' }, el('h3', {}, 'Report'), this.report),
      el('section', { class: 'card' }, el('h3', {}, 'Earlier diagnoses'), this.list));
  }

  async refreshLists() {
    const seq = this.listSeq = (this.listSeq || 0) + 1; // only the newest answer counts
    try {
      const [runs, datasets, diag] = await Promise.all([getAll('/runs', 'runs'), getAll('/datasets', 'datasets'), getJSON('/diagnoses').catch(() => ({ diagnoses: [] }))]);
      if (seq !== this.listSeq) return;
      this.runSelect.replaceChildren(...runs.filter(r => r.scheme_id != null)
        .map(r => el('option', { value: r.scheme_id }, `#${r.id} ${r.name || ''} (scheme ${r.scheme_id})`)));
      this.datasetSelect.replaceChildren(...datasets.map(d => el('option', { value: d.id }, `#${d.id} ${d.name || ''}`)));
      const list = diag.diagnoses || [];
      this.list.replaceChildren(list.length
        ? table('diagnoses-table', [
          d => el('a', { href: '#/diagnose', onclick: ev => { ev.preventDefault(); this.follow(d.id); } }, `#${d.id}`),
          'dataset_id', 'status', d => num(d.progress_pct) + ' %', d => d.chosen_effect || '—', 'created_at'],
        list, ['id', 'dataset', 'status', 'progress', 'chosen effect', 'created'])
        : el('span', { class: 'hint' }, 'none yet'));
    } catch (e) { this.error.textContent = e.message; }
  }

  async start() {
    this.error.textContent = '';
    for (const f of Object.values(this.fields)) f.error.textContent = '';
    const datasetId = Number(this.datasetSelect.value);
    const schemeId = Number(this.runSelect.value);
    if (!datasetId || !schemeId) { this.error.textContent = 'pick a dataset and a run whose scheme to use'; return; }
    // Out-of-limits values are sent as typed: the server is the authority and its 422
    // lands beside the field it names.
    const value = key => Number(this.fields[key].input.value);
    const body = { scheme_id: schemeId, budget_runs: value('budget_runs'), seed: value('seed') };
    if (value('max_particles') !== 0) body.max_particles = value('max_particles');
    try {
      const res = await postJSON(`/datasets/${datasetId}/diagnose`, body);
      this.follow(res.id);
      this.refreshLists();
    } catch (e) {
      const field = e.problem?.field;
      const target = field && this.fields[field.replace(/^\//, '')];
      if (target) target.error.textContent = e.message;
      else this.error.textContent = `${e.status ? e.status + ' ' : ''}${field ? field + ': ' : ''}${e.message}`;
    }
  }

  follow(id) {
    this.stop();
    this.diagnosisId = id;
    this.lastStage = null;
    this.candidateRows = [];
    this.candidates.replaceChildren();
    this.report.replaceChildren(el('p', { class: 'hint' }, `diagnosis #${id}: waiting for the report…`));
    this.source = new EventSource(`/diagnoses/${id}/events`);
    const parse = ev => { try { return JSON.parse(ev.data); } catch { return null; } };
    this.source.addEventListener('progress', ev => {
      const d = parse(ev);
      if (d) { this.lastStage = d.stage; this.showProgress('running', d.stage, d.progress_pct, d.eta_s); }
    });
    this.source.addEventListener('candidate', ev => {
      const d = parse(ev);
      if (!d) return;
      this.candidateRows.push(d);
      this.candidates.replaceChildren(el('h4', {}, 'Candidates tried'), table('diagnosis-candidates-table',
        ['step', 'effect', 'fitted', r => paramText(r.parameters), 'nrmse', 'bic', 'delta_bic_vs_base', 'note'], this.candidateRows,
        ['step', 'effect', 'fitted', 'parameters', 'NRMSE', 'BIC', 'ΔBIC vs base', 'note']));
    });
    const end = () => { this.source?.close(); this.poll(); };
    this.source.addEventListener('done', end);
    this.source.addEventListener('error', ev => { if (ev.data) end(); });
    this.poll();
  }

  showProgress(status, stage, pct, eta) {
    this.progress.replaceChildren(...[el('span', {}, `diagnosis #${this.diagnosisId} `),
      el('span', { class: `status status-${status}` }, status), ' ', progressElement(stage || 'diagnosis', pct, eta),
      ACTIVE.has(status) ? el('button', { type: 'button', onclick: () => postJSON(`/diagnoses/${this.diagnosisId}/cancel`).then(() => this.poll()).catch(e => { this.error.textContent = e.message; }) }, 'Cancel') : null].filter(x => x != null));
  }

  async poll() {
    clearTimeout(this.timer);
    const id = this.diagnosisId;
    try {
      const d = await getJSON(`/diagnoses/${id}`);
      if (id !== this.diagnosisId) return;
      // GET /diagnoses/{id} has no stage; keep the last one the stream announced.
      this.showProgress(d.status, d.stage || this.lastStage, d.progress_pct, d.eta_s);
      if (d.report) { this.renderReport(d); return; }
      if (!ACTIVE.has(d.status)) {
        this.report.replaceChildren(el('p', { class: 'error' }, `${d.status}${d.error ? ': ' + d.error : ''}`));
        this.stop();
        return;
      }
    } catch (e) { this.error.textContent = e.message; }
    this.timer = setTimeout(() => this.poll(), 2000);
  }

  renderReport(d) {
    this.stop();
    const r = d.report;
    const parts = [
      el('p', { class: 'verdict', id: 'diagnosis-verdict' }, el('strong', {}, 'Chosen effect: '), String(r.chosen_effect),
        r.effects?.length > 1 ? ` (effects: ${r.effects.join(', ')})` : '', el('br'), r.verdict || ''),
      el('p', { class: 'hint' }, `pooled NRMSE: calibrated base model ${num(r.nrmse_before)} → with the chosen effects ${num(r.nrmse_after)} · ${num(r.n_readings)} readings, ` +
        `${num(r.n_effective)} effectively independent · ${num(r.runs_used)} DEM runs`),
    ];
    if (r.parameters?.length) parts.push(el('h4', {}, 'Fitted parameters'), table('diagnosis-parameters', ['name', 'value', 'std', 'unit'], r.parameters, ['parameter', 'value', '± std', 'unit']));
    if (r.base_parameters?.length) parts.push(el('h4', {}, 'Base model parameters'), table('diagnosis-base-parameters', ['name', 'value', 'std', 'unit'], r.base_parameters, ['parameter', 'value', '± std', 'unit']));
    // Each error row carries its series' lab unit (kPa, %, mm); NRMSE is relative to the
    // lab series' range. "Before" is the base model *after* calibration, with no effect.
    const errCols = ['curve', 'phase', 'n', e => `${num(e.rmse)} ${e.unit || ''}`.trim(), e => num(e.nrmse)];
    const errHeads = ['curve', 'phase', 'readings', 'RMSE (unit of the series)', 'NRMSE (of the lab range)'];
    const added = r.effects?.length ? r.effects.join(' + ') : 'no effect';
    if (r.error_before?.length) parts.push(el('h4', {}, 'Error of the calibrated base model (before any effect is added)'), table('diagnosis-before', errCols, r.error_before, errHeads));
    if (r.error_after?.length) parts.push(el('h4', {}, `Error after adding ${added} (recalibrated)`), table('diagnosis-after', errCols, r.error_after, errHeads));
    if (r.delta_bic) {
      parts.push(el('h4', {}, 'ΔBIC (negative favours the effect)'),
        el('p', { id: 'diagnosis-delta-bic' }, `vs base model: ${num(r.delta_bic.vs_base)}`));
      if (r.delta_bic.runners_up?.length) parts.push(table('diagnosis-runners-up', ['effect', 'delta_bic'], r.delta_bic.runners_up, ['runner-up effect', 'ΔBIC']));
    }
    if (r.steps?.length) parts.push(el('h4', {}, 'Selection steps'), table('diagnosis-steps', ['step', 'added', 'nrmse_before', 'nrmse_after', 'delta_bic', 'n_effective'], r.steps, ['step', 'added', 'NRMSE before', 'NRMSE after', 'ΔBIC', 'n eff']));
    if (!this.candidateRows?.length && r.candidates?.length) {
      this.candidates.replaceChildren(el('h4', {}, 'Candidates tried'), table('diagnosis-candidates-table',
        ['step', 'effect', 'fitted', c => paramText(c.parameters), 'nrmse', 'bic', 'delta_bic_vs_base', 'note'], r.candidates,
        ['step', 'effect', 'fitted', 'parameters', 'NRMSE', 'BIC', 'ΔBIC vs base', 'note']));
    }
    this.report.replaceChildren(...parts);
    this.refreshLists();
  }

  stop() {
    clearTimeout(this.timer);
    if (this.source) this.source.close();
  }

  close() { this.stop(); this.source = null; this.diagnosisId = null; }
}
