// Closing the loop: ask the service which test effect (seating error, membrane
// compliance, ...) best explains the misfit between a scheme and a dataset, and show the
// report: chosen effect, fitted parameters in the form's words and lab units, error before
// and after as a chart by curve and phase, delta-BIC, verdict; "run with these parameters"
// (the calibrated model's scheme at the σ3 picked, report.model_schemes) and "re-run".
// Before start: the cost (model and DEM runs, minutes), from the service's
// plan of the request start() would send (POST /datasets/{id}/diagnosis-plan). While
// it runs: the stream /diagnoses/{id}/events (progress, candidate, done, error) with an ETA
// from the progress rate, and polling of GET /diagnoses/{id} for the final report.

import { el, getAll, getJSON, postJSON, progressElement, progressEta } from './api.js';
import { renderDiagnosisCurves } from './diagnosis_curves.js';
import { envelopeTable, envelopeText, mohrChart, pqChart } from './envelope.js';
import { printButton, printHeader } from './print_report.js';

// Five significant digits; very large or small magnitudes as 1.2e+8.
const sig = v => (v !== 0 && (Math.abs(v) >= 1e6 || Math.abs(v) < 1e-4) ? v.toExponential(4).replace(/\.?0+e/, 'e') : Number(v.toPrecision(5)));
const num = v => (typeof v === 'number' ? sig(v) : v == null ? '—' : typeof v === 'boolean' ? (v ? 'yes' : 'no') : String(v));

function table(id, cols, rows, headers = cols) {
  return el('div', { class: 'table-scroll' }, el('table', { class: 'grid', id },
    el('tr', {}, headers.map(h => el('th', {}, h))),
    rows.map(r => el('tr', {}, cols.map(c => el('td', {}, typeof c === 'function' ? c(r) : num(r[c])))))));
}

const ACTIVE = new Set(['queued', 'running']);

// The diagnosis's parameters (engine/diagnose: base_parameters, effect_parameters) in the
// form's words and lab units, and how each one changes the scheme diagnosed for "run with
// these parameters" on a report stored without model_schemes (applyParameters: the fitted
// values only, not the calibrated model's boundary, packing and grain cap).
export const PARAMETERS = {
  contact_normal_modulus: { label: 'normal modulus', unit: 'MPa', factor: 1e-6, field: '/micro/normal_modulus_MPa',
    apply: (s, v) => { const r = s.micro.shear_modulus_MPa / s.micro.normal_modulus_MPa; s.micro.normal_modulus_MPa = v / 1e6; s.micro.shear_modulus_MPa = r * v / 1e6; } },
  friction: { label: 'friction', unit: '–', factor: 1, field: '/micro/friction', apply: (s, v) => { s.micro.friction = v; } },
  bond_strength: { label: 'bond normal and shear strength', unit: 'kPa', factor: 1e-3, field: '/micro/bond_normal_strength_kPa',
    apply: (s, v) => { s.micro.bond_normal_strength_kPa = v / 1e3; s.micro.bond_shear_strength_kPa = v / 1e3; } },
  compaction_friction_ratio: { label: 'compaction friction ratio', unit: '–', factor: 1, field: '/specimen/compaction_friction_ratio',
    apply: (s, v) => { s.specimen ||= {}; s.specimen.compaction_friction_ratio = v; } },
  rolling_friction: { label: 'rolling friction', unit: '–', factor: 1, field: '/micro/rolling_friction',
    apply: (s, v) => { s.micro.rolling_friction = v; } },
  // Crushability 0 means the grains do not crush (no strength at all is not what it says).
  grain_crushability: { label: 'crushing strength (from crushability 0.6 MPa / x)', unit: 'MPa', value: v => (v > 0 ? 0.6 / v : 0), field: '/micro/crushing_strength_MPa',
    none: { label: 'grain crushing', text: 'none (grains do not crush)' },
    apply: (s, v) => { s.micro.crushing_strength_MPa = v > 0 ? 0.6 / v : 0; } },
  extra_bond_damage_rate: { label: 'bond corrosion scale (1 + x)', unit: '–', value: v => 1 + v, field: '/effects/bond_corrosion_scale',
    apply: (s, v) => { if (v > 0) { s.effects.accelerated_bond_corrosion = true; s.effects.bond_corrosion_scale = 1 + v; } } },
  direct_effect_a: { label: 'contact creep: rate sensitivity a (rate-and-state)', unit: '–', factor: 1, field: '/creep/direct_effect_a',
    apply: (s, v) => { s.effects.contact_creep_viscosity = v > 0; if (v > 0) s.creep.direct_effect_a = v; } },
  seating_strain: { label: 'seating displacement (strain × height)', unit: 'mm', scheme: (s, v) => v * s.specimen.height_mm, field: '/effects/seating_displacement_mm',
    apply: (s, v) => { s.effects.seating_error = true; s.effects.seating_displacement_mm = v * s.specimen.height_mm; } },
  // K_m = 4 E_m t_m / D [Pa] as the membrane modulus E_m: the service's scheme_value (kPa).
  membrane_stiffness: { label: 'membrane modulus (from K_m = 4 E_m t_m / D)', unit: 'kPa', field: '/effects/membrane_modulus_kPa',
    apply: (s, v) => { s.effects.membrane_compliance = true; s.effects.membrane_modulus_kPa = v; } },
};

function labValue(p, scheme) {
  const d = PARAMETERS[p.name];
  if (!d) return { label: p.name.replace(/_/g, ' '), unit: p.unit || '', value: p.value, std: p.std, field: '' };
  if (d.none && p.value === 0) return { label: d.none.label, unit: '', value: d.none.text, std: null, field: d.field };
  if (p.scheme_value != null) return { label: d.label, unit: d.unit, value: p.scheme_value, std: p.scheme_std ?? null, field: d.field };
  if (d.value) return { label: d.label, unit: d.unit, value: d.value(p.value), std: null, field: d.field };
  if (d.scheme) return { label: d.label, unit: d.unit, value: scheme ? d.scheme(scheme, p.value) : p.value, std: scheme && p.std != null ? d.scheme(scheme, p.std) : null, field: d.field };
  return { label: d.label, unit: d.unit, value: p.value * d.factor, std: p.std != null ? p.std * d.factor : null, field: d.field };
}

// The scheme diagnosed with the fitted values: the fallback of "run with these parameters"
// for a report stored without model_schemes.
export function applyParameters(scheme, parameters) {
  const s = structuredClone(scheme);
  s.micro ||= {}; s.creep ||= {}; s.effects ||= {};
  for (const p of parameters || []) PARAMETERS[p.name]?.apply(s, p.scheme_value ?? p.value);
  return s;
}

// The request limits of POST /datasets/{id}/diagnose, as the server validates them
// (diagnose_options_from_json in server/io/diagnosis_json.cpp; GET /openapi.json does not
// carry them). The browser test sends values just outside them and expects the 422.
export const LIMITS = { budget_runs: [4, 400], max_particles: [0, 1000000], seed: [0, 2 ** 53], relative_density_percent: [0, 100] };

// One line on what a model scheme (report.model_schemes[i].scheme, lab units) runs.
export function modelSchemeText(s) {
  const fx = s.effects || {}, micro = s.micro || {}, loading = s.loading || {};
  const stages = loading.stress_levels?.length || 0;
  const effects = [micro.rolling_friction > 0 && `rolling friction ${num(micro.rolling_friction)}`,
    micro.crushing_strength_MPa > 0 && `crushable grains (${num(micro.crushing_strength_MPa)} MPa)`,
    fx.accelerated_bond_corrosion && `bond corrosion ×${num(fx.bond_corrosion_scale)}`,
    fx.contact_creep_viscosity && `contact creep (rate-and-state a ${num(s.creep?.direct_effect_a)})`,
    fx.seating_error && `seating ${num(fx.seating_displacement_mm)} mm`,
    fx.membrane_compliance && `membrane compliance (E_m ${num(fx.membrane_modulus_kPa)} kPa)`].filter(Boolean);
  return [
    s.specimen?.lateral_boundary === 'grain_pressure' ? 'grain-pressure boundary (no membrane)' : 'bonded membrane',
    s.max_particles > 0 ? `${s.max_particles} grains cap` : 'grains from the gradation',
    `packing grown at porosity ${num(s.specimen?.target_porosity)}`,
    `σ3 ${num(loading.confining_pressure_kPa)} kPa`,
    `shear to ${num(loading.max_axial_strain_pct)} %`,
    stages ? `${stages} creep stage${stages === 1 ? '' : 's'}` : 'no creep stage',
    `effects: ${effects.length ? effects.join(', ') : 'none'}`,
    `seed ${s.seed}`].join(', ');
}

// Effects and artefacts in a lab engineer's words (engine/diagnose/effect.cpp names).
const EFFECT_WORDS = { rolling_resistance: 'rolling resistance of the grains', seating_error: 'a seating error of the platens',
  membrane_compliance: 'membrane compliance', bond_degradation: 'bond degradation', contact_creep_viscosity: 'viscous contact creep',
  moisture_bonding: 'moisture bonding', grain_crushing: 'grain crushing', seating_strain: 'a seating error of the platens',
  membrane_stiffness: 'membrane compliance' };
export const effectWords = e => EFFECT_WORDS[e] || String(e).replace(/_/g, ' ');
const andList = xs => (xs.length < 2 ? xs.join('') : `${xs.slice(0, -1).join(', ')} and ${xs[xs.length - 1]}`);
const pct1 = v => `${(100 * v).toFixed(1)} %`;

// What was added on top of the calibrated base model: the kept effects and the test
// artefacts kept as corrections below the evidence threshold.
export function keptAdditions(r) {
  return [...(r.effects || []), ...(r.artefacts_below_threshold || []).filter(a => !(r.effects || []).includes(a))];
}

// The verdict in one plain sentence, from the report's outcome and numbers (the service's
// verdict, with every figure, follows it).
export function plainVerdict(r) {
  const tol = r.noise_floor?.tolerance_nrmse;
  const within = tol != null && r.nrmse_after <= tol;
  const err = `${pct1(r.nrmse_after)} of the lab range${tol != null ? ` (a right model: about ${pct1(tol)})` : ''}`;
  const kept = keptAdditions(r).map(effectWords);
  if (r.outcome === 'no_effect_needed' || (!r.outcome && !kept.length && within))
    return `The calibrated model fits the lab ${within ? 'within' : 'close to'} the noise floor without any extra effect: error ${err}.`;
  if (r.outcome === 'effect_found' || (!r.outcome && r.chosen_effect && r.chosen_effect !== 'unexplained'))
    return `The lab curves are explained by the calibrated model with ${andList(kept)}: error ${pct1(r.nrmse_before)} → ${err}.`;
  return `No effect in the catalog explains the misfit: the model stays ${err} off${kept.length ? `, with ${andList(kept)} helping in part` : ''}.`;
}

const minutesText = m => (m < 1 ? '< 1 min' : m < 90 ? `${Math.round(m)} min` : `${(m / 60).toFixed(1)} h`);
const rangeText = (lo, hi) => (minutesText(lo) === minutesText(hi) ? minutesText(lo) : `${minutesText(lo)} – ${minutesText(hi)}`);

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
      const id = `diagnose-${key.replace(/_/g, '-')}`;
      const input = el('input', { type: 'number', id, value, min, max, step: 1, title });
      const error = el('span', { class: 'field-error', id: `${id}-error`, role: 'alert' });
      this.fields[key] = { input, error };
      return el('div', { class: 'diagnose-option field' },
        el('label', { for: id }, `${label}${unit ? ' (' + unit + ')' : ''}`), input,
        el('span', { class: 'limits' }, `${min}…${max === 2 ** 53 ? '2⁵³' : max}`), error);
    };
    this.error = el('div', { class: 'field-error', id: 'diagnose-error', role: 'alert' });
    this.cost = el('div', { class: 'estimate', id: 'diagnose-cost', 'aria-live': 'polite' });
    this.progress = el('div', { id: 'diagnosis-progress' }, el('span', { class: 'hint' }, 'no diagnosis selected'));
    this.candidates = el('div', { id: 'diagnosis-candidates' });
    this.report = el('div', { id: 'diagnosis-report' });
    this.list = el('div', { id: 'diagnosis-list' });
    this.container.replaceChildren(
      el('h2', { class: 'print-hide' }, 'Diagnosis'),
      el('section', { class: 'card print-hide' },
        el('p', { class: 'hint' }, 'Calibrates the base model to the dataset, then ranks the candidate effects (rolling resistance, grain breakage, seating error, membrane compliance, ...) by their residual signature, fits the best ones as augmented models and keeps one only if it lowers BIC (with an effective number of readings). The scheme is taken from the chosen run. The budget bounds the calibration runs; each candidate costs further DEM runs.'),
        el('div', { class: 'row' },
          el('label', {}, 'dataset ', this.datasetSelect), el('label', {}, 'scheme of run ', this.runSelect)),
        el('div', { class: 'row' },
          field('budget_runs', 'calibration budget', 'DEM runs', 12),
          field('max_particles', 'max particles per run', '', 200, 'the calibration specimen; 0 = as in the scheme'),
          field('seed', 'seed', '', 1),
          field('relative_density_percent', 'specimen relative density D_r', '%', '',
            'blank = not stated: the model calibrates its packing density; stated, it is held')),
        this.cost,
        el('div', { class: 'row' }, el('button', { type: 'button', id: 'diagnose-button', onclick: () => this.start() }, 'Diagnose')),
        this.error),
      el('section', { class: 'card print-hide' }, el('h3', {}, 'Progress'), this.progress),
      el('section', { class: 'card' }, el('h3', {}, 'Report'), this.report, this.candidates),
      el('section', { class: 'card print-hide' }, el('h3', {}, 'Earlier diagnoses'), this.list));
    const recost = () => { this.clearCostData(); clearTimeout(this.costTimer); this.costTimer = setTimeout(() => this.estimateCost(), 300); };
    for (const f of Object.values(this.fields)) f.input.addEventListener('input', recost);
    this.runSelect.addEventListener('change', recost);
    this.datasetSelect.addEventListener('change', recost);
  }

  // The body of POST /datasets/{id}/diagnose from the form, or null without a run to take
  // the scheme from. Out-of-limits values are sent as typed: the server is the authority.
  requestBody() {
    const schemeId = Number(this.runSelect.value);
    if (!schemeId) return null;
    const value = key => Number(this.fields[key].input.value);
    const body = { scheme_id: schemeId, budget_runs: value('budget_runs'), seed: value('seed'), max_particles: value('max_particles') };
    if (this.fields.relative_density_percent.input.value !== '') body.relative_density_percent = value('relative_density_percent');
    return body;
  }

  // The plan's numbers on #diagnose-cost belong to the form as it was: gone while it changes.
  clearCostData() {
    for (const k of ['runsLow', 'runsHigh', 'minutesLow', 'minutesExpected', 'minutesHigh']) delete this.cost.dataset[k];
  }

  // The cost of the diagnosis start() would request, as the service plans it
  // (POST /datasets/{id}/diagnosis-plan, docs/api.md): model runs from the engine's plan
  // (the low end: calibration, noise floor, base uncertainty; at most: every candidate),
  // each one DEM run per lab condition (σ3) and packing, and minutes for the whole
  // diagnosis at the concurrency it would use. Only the newest answer is shown.
  async estimateCost() {
    const seq = this.costSeq = (this.costSeq || 0) + 1;
    const datasetId = Number(this.datasetSelect.value), body = this.requestBody();
    this.clearCostData();
    if (!datasetId || !body) {
      this.cost.replaceChildren(el('span', { class: 'hint' }, 'pick a dataset and a run to see the cost'));
      return;
    }
    try {
      const plan = await postJSON(`/datasets/${datasetId}/diagnosis-plan`, body);
      if (seq !== this.costSeq) return;
      const m = plan.minutes_estimate, o = plan.options;
      const pressures = plan.lab_conditions.map(c => `${num(c.confining_kPa)} kPa`).join(', ');
      const engineRuns = plan.engine_runs_per_model_run * o.packings_per_run;
      this.cost.dataset.runsLow = String(plan.model_runs_low);
      this.cost.dataset.runsHigh = String(plan.model_runs_at_most);
      this.cost.dataset.minutesLow = String(m.low);
      this.cost.dataset.minutesHigh = String(m.high);
      this.cost.dataset.minutesExpected = String(m.expected);
      this.cost.replaceChildren(el('strong', {}, 'Cost: '),
        `${plan.model_runs_low} to ${plan.model_runs_at_most} model runs, each ${engineRuns} DEM run${engineRuns === 1 ? '' : 's'} of ≈ ${plan.grains} grains (σ3 ${pressures})`,
        ` · in all about ${minutesText(m.expected)} expected (${rangeText(m.low, m.high)}) with ${Math.min(o.concurrency, o.batch_runs)} at once`);
    } catch (err) {
      if (seq !== this.costSeq) return;
      this.cost.replaceChildren(el('strong', {}, 'Cost: '), `unknown (${err.problem?.field ? err.problem.field + ': ' : ''}${err.message})`);
    }
  }

  async refreshLists() {
    const seq = this.listSeq = (this.listSeq || 0) + 1; // only the newest answer counts
    try {
      const [runs, datasets, diag] = await Promise.all([getAll('/runs', 'runs'), getAll('/datasets', 'datasets'), getJSON('/diagnoses').catch(() => ({ diagnoses: [] }))]);
      if (seq !== this.listSeq) return;
      const keep = this.runSelect.value;
      this.runSelect.replaceChildren(...runs.filter(r => r.scheme_id != null)
        .map(r => el('option', { value: r.scheme_id }, `#${r.id} ${r.name || ''} (scheme ${r.scheme_id})`)));
      if (keep) this.runSelect.value = keep;
      const keepSet = this.datasetSelect.value;
      this.datasetSelect.replaceChildren(...datasets.map(d => el('option', { value: d.id }, `#${d.id} ${d.name || ''}`)));
      if (keepSet) this.datasetSelect.value = keepSet;
      const list = diag.diagnoses || [];
      this.list.replaceChildren(list.length
        ? table('diagnoses-table', [
          d => el('a', { href: '#/diagnose', onclick: ev => { ev.preventDefault(); this.follow(d.id); } }, `#${d.id}`),
          'dataset_id', 'status', d => num(d.progress_pct) + ' %', d => d.chosen_effect || '—', 'created_at'],
        list, ['id', 'dataset', 'status', 'progress', 'chosen effect', 'created'])
        : el('span', { class: 'hint' }, 'none yet'));
      this.estimateCost();
    } catch (e) { this.error.textContent = e.message; }
  }

  async start(body = null, datasetId = null) {
    this.error.textContent = '';
    for (const f of Object.values(this.fields)) f.error.textContent = '';
    datasetId ??= Number(this.datasetSelect.value);
    if (!body) {
      // The server's 422 lands beside the field it names.
      body = this.requestBody();
      if (!datasetId || !body) { this.error.textContent = 'pick a dataset and a run whose scheme to use'; return; }
    }
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
    this.rate = null;
    this.candidateRows = [];
    this.candidates.replaceChildren();
    this.report.replaceChildren(el('p', { class: 'hint' }, `diagnosis #${id}: waiting for the report…`));
    this.source = new EventSource(`/diagnoses/${id}/events`);
    const parse = ev => { try { return JSON.parse(ev.data); } catch { return null; } };
    this.source.addEventListener('progress', ev => {
      const d = parse(ev);
      if (d) { this.lastStage = d.stage; this.showProgress('running', d.stage, d.progress_pct, this.eta(d.progress_pct)); }
    });
    this.source.addEventListener('candidate', ev => {
      const d = parse(ev);
      if (!d) return;
      this.candidateRows.push(d);
      this.renderCandidates(this.candidateRows);
    });
    const end = () => { this.source?.close(); this.poll(); };
    this.source.addEventListener('done', end);
    this.source.addEventListener('error', ev => { if (ev.data) end(); });
    this.poll();
  }

  // The diagnosis's stream has no ETA: the page's one estimate from its progress (api.js
  // progressEta), the same the header's activity line shows for it.
  eta(pct) { return progressEta(`diagnosis-${this.diagnosisId}`, pct); }

  renderCandidates(rows) {
    // A candidate not fitted has no NRMSE or BIC: shown as "not fitted", not as 0.
    const fitted = (r, k) => (r.fitted ? num(r[k]) : '—');
    this.candidates.replaceChildren(el('h4', {}, 'Candidates tried'), table('diagnosis-candidates-table',
      ['step', 'effect', r => (r.fitted ? 'yes' : 'not fitted'), r => this.paramText(r.parameters), r => fitted(r, 'nrmse'), r => fitted(r, 'bic'), r => fitted(r, 'delta_bic_vs_base'), 'note'], rows,
      ['step', 'effect', 'fitted', 'parameters', 'NRMSE', 'BIC', 'ΔBIC vs base', 'note']));
  }

  paramText(ps) {
    return (ps || []).map(p => { const l = labValue(p, this.scheme); return `${l.label} = ${num(l.value)}${l.unit && l.unit !== '–' && l.unit !== '×' ? ' ' + l.unit : ''}`; }).join('; ');
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
      this.diagnosis = d;
      this.scheme = d.scheme || null;
      // GET /diagnoses/{id} has no stage; keep the last one the stream announced.
      this.showProgress(d.status, d.stage || this.lastStage, d.progress_pct, ACTIVE.has(d.status) ? this.eta(d.progress_pct) : null);
      if (d.report) { this.renderReport(d); return; }
      if (!ACTIVE.has(d.status)) {
        this.report.replaceChildren(el('p', { class: 'error' }, `${d.status}${d.error ? ': ' + d.error : ''}`));
        this.stop();
        return;
      }
    } catch (e) { this.error.textContent = e.message; }
    this.timer = setTimeout(() => this.poll(), 2000);
  }

  paramTable(id, ps) {
    return table(id, [p => labValue(p, this.scheme).label, p => num(labValue(p, this.scheme).value), p => num(labValue(p, this.scheme).std),
      p => labValue(p, this.scheme).unit, p => labValue(p, this.scheme).field], ps, ['parameter (as in the form)', 'value', '± std', 'unit', 'form field']);
  }

  // NRMSE per curve and phase, before and after the kept effects, as horizontal bars.
  residualChart(before, after) {
    const key = e => `${e.curve} · ${e.phase}`;
    const rows = [...new Set([...(before || []), ...(after || [])].map(key))];
    const get = (list, k) => (list || []).find(e => key(e) === k);
    const max = Math.max(1e-9, ...[...(before || []), ...(after || [])].map(e => e.nrmse || 0));
    const bar = (e, cls) => el('div', { class: `bar ${cls}`, style: `width:${Math.max(0.5, 100 * (e?.nrmse || 0) / max)}%`,
      title: e ? `NRMSE ${num(e.nrmse)} · RMSE ${num(e.rmse)} ${e.unit || ''}` : 'not computed' });
    return el('figure', { class: 'bars', id: 'diagnosis-residual-chart', role: 'img',
      'aria-label': `NRMSE by curve and phase before and after the effects: ${rows.map(k => `${k} ${num(get(before, k)?.nrmse)} → ${num(get(after, k)?.nrmse)}`).join('; ')}` },
    el('figcaption', {}, 'Residual (NRMSE of the lab range) by curve and phase: ',
      el('span', { class: 'swatch before' }), ' calibrated base model ', el('span', { class: 'swatch after' }), ' with the kept effects'),
    ...rows.map(k => el('div', { class: 'bar-row' }, el('span', { class: 'bar-label' }, k),
      el('div', { class: 'bar-pair' }, bar(get(before, k), 'before'), bar(get(after, k), 'after')),
      el('span', { class: 'bar-value' }, `${num(get(before, k)?.nrmse)} → ${num(get(after, k)?.nrmse)}`))));
  }

  // The scheme "run with these parameters" posts: the calibrated model's at the σ3 picked
  // (report.model_schemes, built by the service with the engine's DemForwardModel), or, for
  // a report stored without it, the scheme diagnosed with the fitted values.
  fittedScheme(r) {
    const schemes = r.model_schemes || [];
    if (schemes.length) return structuredClone(schemes[Number(this.conditionSelect?.value || 0)]?.scheme || schemes[0].scheme);
    if (!this.scheme) throw new Error('the diagnosis carries no scheme');
    const scheme = applyParameters(this.scheme, [...(r.base_parameters || []), ...(r.parameters || [])]);
    scheme.name = `${scheme.name || 'scheme'} · fitted`.slice(0, 120);
    return scheme;
  }

  async runFitted(r) {
    this.error.textContent = '';
    try {
      const res = await postJSON('/runs', { scheme: this.fittedScheme(r) });
      location.hash = `#/runs/${res.id}`;
    } catch (e) { this.error.textContent = `run with these parameters: ${e.message}`; }
  }

  // What "run with these parameters" runs: a σ3 picker over the lab conditions (null
  // without model_schemes) and one line describing the scheme picked.
  fittedRunInfo(r) {
    const schemes = r.model_schemes || [];
    const line = el('p', { class: 'hint', id: 'diagnosis-model-scheme' });
    if (!schemes.length) {
      this.conditionSelect = null;
      line.textContent = 'runs the scheme diagnosed with the fitted values (this report has no calibrated model scheme): its boundary, packing and grain cap are the scheme\'s, not the calibrated model\'s, so its curves may differ from the report\'s';
      return { picker: null, line };
    }
    this.conditionSelect = el('select', { id: 'diagnosis-run-condition', 'aria-label': 'confining pressure of the run' },
      schemes.map((c, i) => el('option', { value: i }, `σ3 ${num(c.confining_kPa)} kPa`)));
    const show = () => { line.textContent = `runs the calibrated model: ${modelSchemeText(this.fittedScheme(r))}`; };
    this.conditionSelect.addEventListener('change', show);
    show();
    return { picker: el('label', {}, 'at ', this.conditionSelect), line };
  }

  renderReport(d) {
    this.stop();
    const r = d.report;
    const fitted = this.fittedRunInfo(r);
    const conditions = () => `diagnosis #${d.id} of dataset #${d.dataset_id}${this.scheme?.name ? ' · scheme ' + this.scheme.name : ''}`;
    this.curvesBox = el('div', { id: 'diagnosis-curves' }, el('p', { class: 'hint' }, 'loading the lab readings…'));
    this.envelopeBox = el('div', { id: 'diagnosis-envelope' });
    const parts = [
      printHeader(`Diagnosis #${d.id}`, conditions(), this.scheme),
      el('p', { class: 'verdict', id: 'diagnosis-plain-verdict' }, el('strong', {}, plainVerdict(r))),
      el('p', { class: 'hint', id: 'diagnosis-verdict' }, el('strong', {}, 'Chosen effect: '), String(r.chosen_effect),
        r.effects?.length > 1 ? ` (effects: ${r.effects.join(', ')})` : '', el('br'), r.verdict || ''),
      el('p', { class: 'hint' }, `pooled NRMSE: calibrated base model ${num(r.nrmse_before)} → with the chosen effects ${num(r.nrmse_after)} · ${num(r.n_readings)} readings, ` +
        `${num(r.n_effective)} effectively independent · ${num(r.runs_used)} DEM runs`),
      el('div', { class: 'row' },
        el('button', { type: 'button', id: 'diagnosis-run-fitted', onclick: () => this.runFitted(r) }, 'Run with these parameters'),
        fitted.picker,
        el('button', { type: 'button', id: 'diagnosis-rerun', onclick: () => this.rerun(d) }, 'Re-run this diagnosis'),
        printButton('diagnosis-print')),
      fitted.line,
      el('h4', {}, 'Model against lab for every σ3'), this.curvesBox,
      el('h4', {}, 'Strength envelope: lab, calibrated base and final model'), this.envelopeBox,
    ];
    if (r.error_before?.length || r.error_after?.length) parts.push(this.residualChart(r.error_before, r.error_after));
    // The effects' parameters and the recalibrated base model's: two different sets.
    if (r.parameters?.length) parts.push(el('h4', {}, `Parameters of the kept effects (${r.effects?.join(' + ') || r.chosen_effect})`), this.paramTable('diagnosis-parameters', r.parameters));
    if (r.base_parameters?.length) parts.push(el('h4', {}, 'Calibrated base model'), this.paramTable('diagnosis-base-parameters', r.base_parameters));
    // Each error row carries its series' lab unit (kPa, %, mm); NRMSE is relative to the
    // lab series' range. "Before" is the base model *after* calibration, with no effect.
    const errCols = ['curve', 'phase', 'n', e => `${num(e.rmse)} ${e.unit || ''}`.trim(), e => num(e.nrmse)];
    const errHeads = ['curve', 'phase', 'readings', 'RMSE (unit of the series)', 'NRMSE (of the lab range)'];
    // Kept effects and the artefacts kept as corrections are both added to the final model.
    const added = keptAdditions(r);
    const afterTitle = added.length ? `Error after adding ${added.join(' + ')} (recalibrated)` : 'Error of the final model (nothing added to the calibrated base)';
    if (r.error_before?.length) parts.push(el('h4', {}, 'Error of the calibrated base model (before any effect is added)'), table('diagnosis-before', errCols, r.error_before, errHeads));
    if (r.error_after?.length) parts.push(el('h4', {}, afterTitle), table('diagnosis-after', errCols, r.error_after, errHeads));
    if (r.delta_bic) {
      parts.push(el('h4', {}, 'ΔBIC (negative favours the effect)'),
        el('p', { id: 'diagnosis-delta-bic' }, `vs base model: ${num(r.delta_bic.vs_base)}`));
      if (r.delta_bic.runners_up?.length) parts.push(table('diagnosis-runners-up', ['effect', 'delta_bic'], r.delta_bic.runners_up, ['runner-up effect', 'ΔBIC']));
    }
    // A step that kept nothing says so (an empty "added" cell read as a missing value).
    if (r.steps?.length) parts.push(el('h4', {}, 'Selection steps'), table('diagnosis-steps', ['step', s => s.added || 'nothing kept', 'nrmse_before', 'nrmse_after', 'delta_bic', 'n_effective'], r.steps, ['step', 'added', 'NRMSE before', 'NRMSE after', 'ΔBIC', 'n eff']));
    parts.push(el('p', { class: 'hint' }, `"Run with these parameters" runs ${fitted.picker ? 'the calibrated model at the σ3 picked' : 'the fitted values on the scheme diagnosed'}; the curves above are the report's own model runs.`));
    if (!this.candidateRows?.length && r.candidates?.length) this.renderCandidates(r.candidates);
    this.report.replaceChildren(...parts);
    this.renderCurves(d, conditions);
    this.refreshLists();
  }

  // The lab readings and the lab's envelope (GET /datasets/{id}, /datasets/{id}/envelope)
  // beside the report's model curves and envelopes.
  async renderCurves(d, conditions) {
    const r = d.report, id = d.id;
    const [dataset, labEnvelope] = await Promise.all([getJSON(`/datasets/${d.dataset_id}`).catch(() => null),
      getJSON(`/datasets/${d.dataset_id}/envelope`).catch(() => null)]);
    if (id !== this.diagnosisId) return;
    for (const c of this.charts || []) c.destroy();
    this.charts = renderDiagnosisCurves(this.curvesBox, r, dataset, conditions);
    if (!dataset) this.curvesBox.prepend(el('p', { class: 'hint' }, `dataset #${d.dataset_id} is gone: model curves only`));
    const sets = [{ label: 'lab', envelope: labEnvelope }, { label: 'calibrated base', envelope: r.strength_envelope?.base, dash: [6, 4] },
      { label: 'final model', envelope: r.strength_envelope?.final }].filter(x => x.envelope);
    if (!r.strength_envelope) this.envelopeBox.replaceChildren(el('p', { class: 'hint' }, 'This report carries no model envelope (stored before it was kept); the lab\'s: ' + envelopeText(labEnvelope)));
    else this.envelopeBox.replaceChildren(envelopeTable('diagnosis-envelope-table', sets));
    const grid = el('div', { class: 'plot-grid' });
    this.envelopeBox.append(grid);
    this.charts.push(mohrChart(grid, 'diagnosis-mohr', sets, conditions), pqChart(grid, 'diagnosis-pq', sets, conditions));
  }

  rerun(d) {
    const options = d.options || {};
    const body = { ...options };
    if (!this.scheme) { this.error.textContent = 'the diagnosis carries no scheme'; return; }
    body.scheme = this.scheme;
    this.start(body, d.dataset_id);
  }

  stop() {
    clearTimeout(this.timer);
    if (this.source) this.source.close();
  }

  close() { this.stop(); for (const c of this.charts || []) c.destroy(); clearTimeout(this.costTimer); this.source = null; this.diagnosisId = null; }
}
