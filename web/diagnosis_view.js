// Closing the loop: ask the service which test effect (seating error, membrane
// compliance, ...) best explains the misfit between a scheme and a dataset, and show the
// report: chosen effect, fitted parameters, error before/after, delta-BIC, verdict.
// Progress comes from the SSE stream /diagnoses/{id}/events, with polling of
// GET /diagnoses/{id} as the fallback that also fetches the final report.

import { el, getJSON, postJSON, progressElement } from './api.js';

const num = v => (typeof v === 'number' ? Number(v.toPrecision(5)) : v == null ? '—' : String(v));

function table(id, cols, rows, headers = cols) {
  return el('table', { class: 'grid', id },
    el('tr', {}, headers.map(h => el('th', {}, h))),
    rows.map(r => el('tr', {}, cols.map(c => el('td', {}, num(r[c]))))));
}

export class DiagnosisView {
  constructor(container) {
    this.container = container;
    this.timer = null;
    this.source = null;
    this.build();
    this.refreshLists();
  }

  build() {
    this.datasetSelect = el('select', { id: 'diagnose-dataset' });
    this.runSelect = el('select', { id: 'diagnose-run' });
    this.budget = el('input', { type: 'number', id: 'diagnose-budget', value: 24, min: 1, max: 500, step: 1 });
    this.seed = el('input', { type: 'number', id: 'diagnose-seed', value: 1, step: 1 });
    this.error = el('div', { class: 'field-error', role: 'alert' });
    this.progress = el('div', { id: 'diagnosis-progress' });
    this.candidates = el('ul', { class: 'candidates' });
    this.report = el('div', { id: 'diagnosis-report' });
    this.container.replaceChildren(
      el('h2', {}, 'Diagnosis'),
      el('section', { class: 'card' },
        el('p', { class: 'hint' }, 'Fits the base model and each candidate test effect to the dataset and ranks them by BIC. The scheme is taken from the chosen run.'),
        el('div', { class: 'row' },
          el('label', {}, 'dataset ', this.datasetSelect), el('label', {}, 'scheme of run ', this.runSelect),
          el('label', {}, 'budget (runs) ', this.budget), el('label', {}, 'seed ', this.seed),
          el('button', { type: 'button', id: 'diagnose-button', onclick: () => this.start() }, 'Diagnose'),
          el('input', { type: 'number', id: 'diagnosis-open-id', placeholder: 'open id', min: 1, style: 'width:6em' }),
          el('button', { type: 'button', onclick: () => { const v = Number(document.getElementById('diagnosis-open-id').value); if (v) this.follow(v); } }, 'Open')),
        this.error),
      el('section', { class: 'card' }, el('h3', {}, 'Progress'), this.progress, this.candidates),
      el('section', { class: 'card' }, el('h3', {}, 'Report'), this.report));
  }

  async refreshLists() {
    try {
      const [{ runs }, { datasets }] = await Promise.all([getJSON('/runs'), getJSON('/datasets')]);
      this.runSelect.replaceChildren(...runs.filter(r => r.scheme_id != null)
        .map(r => el('option', { value: r.scheme_id }, `#${r.id} ${r.name || ''} (scheme ${r.scheme_id})`)));
      this.datasetSelect.replaceChildren(...datasets.map(d => el('option', { value: d.id }, `#${d.id} ${d.name || ''}`)));
    } catch (e) { this.error.textContent = e.message; }
  }

  async start() {
    this.error.textContent = '';
    const datasetId = Number(this.datasetSelect.value);
    const schemeId = Number(this.runSelect.value);
    if (!datasetId || !schemeId) { this.error.textContent = 'pick a dataset and a run whose scheme to use'; return; }
    try {
      const res = await postJSON(`/datasets/${datasetId}/diagnose`,
        { scheme_id: schemeId, budget_runs: Number(this.budget.value), seed: Number(this.seed.value) });
      this.follow(res.id);
    } catch (e) {
      const field = e.problem?.field;
      this.error.textContent = `${field ? field + ': ' : ''}${e.message}`;
    }
  }

  follow(id) {
    this.stop();
    this.diagnosisId = id;
    this.candidates.replaceChildren();
    this.report.replaceChildren(el('p', { class: 'hint' }, `diagnosis #${id} running…`));
    this.source = new EventSource(`/diagnoses/${id}/events`);
    const parse = ev => { try { return JSON.parse(ev.data); } catch { return null; } };
    this.source.addEventListener('progress', ev => {
      const d = parse(ev);
      if (d) this.progress.replaceChildren(progressElement(d.stage || d.phase || 'diagnosis', d.progress_pct, d.eta_s));
    });
    this.source.addEventListener('candidate', ev => {
      const d = parse(ev);
      if (d) this.candidates.append(el('li', {}, Object.entries(d).map(([k, v]) => `${k}: ${num(v)}`).join(' · ')));
    });
    const end = () => { this.source?.close(); this.poll(); };
    this.source.addEventListener('done', end);
    this.source.addEventListener('error', ev => { if (ev.data) end(); });
    this.poll();
  }

  async poll() {
    clearTimeout(this.timer);
    try {
      const d = await getJSON(`/diagnoses/${this.diagnosisId}`);
      if (!this.source || this.source.readyState === EventSource.CLOSED || d.status !== 'running') {
        this.progress.replaceChildren(el('span', { class: `status status-${d.status}` }, d.status), ' ',
          progressElement(d.stage || 'diagnosis', d.progress_pct, d.eta_s));
      }
      if (d.report) { this.renderReport(d); return; }
      if (d.status === 'failed' || d.status === 'cancelled') {
        this.report.replaceChildren(el('p', { class: 'error' }, d.error || d.detail || d.status));
        return;
      }
    } catch (e) { this.error.textContent = e.message; }
    this.timer = setTimeout(() => this.poll(), 2000);
  }

  renderReport(d) {
    this.stop();
    const r = d.report;
    const parts = [
      el('p', { class: 'verdict', id: 'diagnosis-verdict' }, el('strong', {}, 'Chosen effect: '), String(r.chosen_effect), el('br'), r.verdict || ''),
    ];
    if (r.parameters?.length) parts.push(el('h4', {}, 'Fitted parameters'), table('diagnosis-parameters', ['name', 'value', 'std'], r.parameters, ['parameter', 'value', '± std']));
    const errCols = ['curve', 'phase', 'rmse', 'nrmse'];
    if (r.error_before?.length) parts.push(el('h4', {}, 'Error before calibration'), table('diagnosis-before', errCols, r.error_before));
    if (r.error_after?.length) parts.push(el('h4', {}, 'Error after calibration'), table('diagnosis-after', errCols, r.error_after));
    if (r.delta_bic) {
      parts.push(el('h4', {}, 'ΔBIC (negative favours the effect)'),
        el('p', {}, `vs base model: ${num(r.delta_bic.vs_base)}`));
      if (r.delta_bic.runners_up?.length) parts.push(table('diagnosis-runners-up', ['effect', 'delta_bic'], r.delta_bic.runners_up, ['runner-up effect', 'ΔBIC']));
    }
    this.report.replaceChildren(...parts);
  }

  stop() {
    clearTimeout(this.timer);
    if (this.source) { this.source.close(); }
  }

  close() { this.stop(); this.source = null; }
}
