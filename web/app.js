// Page shell: hash routes (#/new, #/runs, #/runs/7, #/compare, #/diagnose), the new-run
// form, the runs list and the activity line in the header that shows every active run's
// stage, progress and ETA wherever the user is on the page.

import { el, getJSON, getList, moreButton, PAGE, postJSON, ProblemError, progressElement, progressEta } from './api.js';
import { SchemeForm } from './scheme_form.js';
import { RunView } from './run_view.js';
import { CompareView } from './compare_view.js';
import { DiagnosisView } from './diagnosis_view.js';
import { downloadBlob } from './chart.js';

const main = document.getElementById('main');
const activity = document.getElementById('activity');
let current = null; // the view object of the current route (closed on navigation)

// ---- New run ---------------------------------------------------------------------------

// What each paper group tests (seed paper, Table 2): A-B-C vary the confining pressure at
// the optimum moisture, B-D-E the moisture at 100 kPa; B belongs to both series.
const GROUP_ROLE = {
  A: 'lowest confining pressure of the σ3 series (A–B–C)',
  B: 'the reference: σ3 series (A–B–C) and moisture series (B–D–E)',
  C: 'highest confining pressure of the σ3 series (A–B–C)',
  D: 'wetter than optimum: moisture series (B–D–E)',
  E: 'wettest: moisture series (B–D–E), weakest bonds',
};

function presetCard(p, onpick) {
  const sc = p.scheme || {};
  const sigma3 = sc.loading?.confining_pressure_kPa, w = sc.specimen?.moisture_content_pct;
  const levels = (sc.loading?.stress_levels || []).join(' / ');
  const days = (sc.loading?.stage_durations_min || []).reduce((a, b) => a + b, 0) / 1440;
  return el('button', { type: 'button', class: 'preset card-button', dataset: { preset: p.name }, 'aria-pressed': 'false', onclick: () => onpick(p.name) },
    el('span', { class: 'preset-name' }, `Group ${p.name}`),
    el('span', { class: 'preset-facts' }, `σ3 = ${tidy(sigma3)} kPa · w = ${tidy(w)} %`),
    el('span', { class: 'preset-role' }, GROUP_ROLE[p.name] || p.description || ''),
    el('span', { class: 'hint' }, `S = ${levels}${days ? ` · ${Number(days.toFixed(1))} days of creep (model time)` : ''}`));
}

const tidy = v => (typeof v === 'number' ? Number(v.toPrecision(10)) : v);
const minutesText = m => (m < 1 ? '< 1 min' : m < 90 ? `${Math.round(m)} min` : `${(m / 60).toFixed(1)} h`);

async function showNewRun() {
  const presetBox = el('div', { class: 'presets', id: 'presets', role: 'group', 'aria-label': 'paper group presets' });
  const formBox = el('div', { id: 'scheme-form' });
  const formError = el('div', { class: 'field-error', id: 'form-error', role: 'alert' });
  const submit = el('button', { type: 'submit', id: 'submit-run' }, 'Submit run');
  const estimate = el('div', { class: 'estimate', id: 'estimate', 'aria-live': 'polite' }, el('span', { class: 'hint' }, 'estimating…'));
  // The same scheme as JSON: for pasting a saved scheme or editing what the form cannot.
  const jsonArea = el('textarea', { id: 'scheme-json', rows: 18, spellcheck: 'false', 'aria-label': 'the scheme as JSON' });
  const jsonError = el('span', { class: 'field-error' });
  const jsonBox = el('details', { class: 'json-box' }, el('summary', {}, 'Scheme as JSON'), jsonArea,
    el('div', { class: 'row' },
      el('button', { type: 'button', onclick: () => { jsonArea.value = JSON.stringify(schemeForm.scheme(), null, 2); } }, 'From form'),
      el('button', { type: 'button', onclick: () => {
        try { schemeForm.load(JSON.parse(jsonArea.value)); jsonError.textContent = ''; scheduleEstimate(); } catch (e) { jsonError.textContent = e.message; }
      } }, 'To form'),
      el('button', { type: 'button', onclick: () => downloadBlob(new Blob([JSON.stringify(schemeForm.scheme(), null, 2)], { type: 'application/json' }),
        `${(schemeForm.scheme().name || 'scheme').replace(/[^A-Za-z0-9_-]+/g, '_')}.json`) }, 'Download JSON'),
      jsonError));
  jsonBox.addEventListener('toggle', () => { if (jsonBox.open) jsonArea.value = JSON.stringify(schemeForm.scheme(), null, 2); });
  const form = el('form', { id: 'new-run', novalidate: true, 'aria-label': 'new triaxial test' }, formBox,
    el('div', { class: 'submit-row' }, estimate, el('div', { class: 'row' }, submit)), formError, jsonBox);
  main.replaceChildren(
    el('section', { class: 'intro' },
      el('h2', {}, 'Triaxial and creep tests of coarse-grained soil, simulated grain by grain'),
      el('p', {}, 'This tool runs a discrete-element (DEM) twin of a drained triaxial test: it builds a specimen of ' +
        'spheres inside a rubber-like membrane, consolidates it to the confining pressure σ3, shears it to find the ' +
        'peak deviator stress q_f, then loads a second, identical specimen in stages of q = S · q_f and lets each ' +
        'stage creep for its duration. You see q, volumetric strain and creep deformation grow live, can overlay ' +
        'your lab readings, compare them with the model and ask which test effect explains the difference.'),
      el('p', { class: 'hint', id: 'paper-note' }, 'The presets are the groups of Table 2 of "Triaxial Creep Test and Particle Flow Simulation of ' +
        'Coarse-Grained Soil Embankment Filler". Creep durations ("10 days of creep") are model time: the simulated ' +
        'physical time of the creep law, reached in minutes of computing, not days.')),
    el('h3', {}, 'Start from a test of the paper'), presetBox,
    el('h3', {}, 'Your test'),
    el('p', { class: 'hint' }, 'Units are in the labels, limits under each field. Compression is positive.'),
    form);
  const schemeForm = new SchemeForm(formBox);
  let presets = [];
  try {
    const [p, schema] = await Promise.all([getJSON('/presets'), getJSON('/schema/scheme').catch(() => ({}))]);
    presets = p.presets || [];
    schemeForm.setSchema(schema);
  } catch (e) { formError.textContent = `cannot load presets: ${e.message}`; return; }

  // The estimate follows every edit, half a second after the last keystroke; an older
  // answer never replaces a newer one.
  let estimateTimer = null, estimateSeq = 0;
  const runEstimate = async () => {
    const seq = ++estimateSeq;
    try {
      const e = await postJSON('/estimate', schemeForm.scheme());
      if (seq !== estimateSeq) return;
      const m = e.minutes_estimate || {};
      estimate.dataset.grains = e.grains;
      estimate.dataset.minutesLow = m.low;
      estimate.dataset.minutesHigh = m.high;
      estimate.replaceChildren(
        el('div', { class: 'estimate-line' }, el('strong', {}, 'Estimate: '),
          `≈ ${e.grains.toLocaleString('en')} grains + ${e.membrane_particles.toLocaleString('en')} membrane particles · ` +
          `≈ ${Number(e.steps).toLocaleString('en')} steps · ${minutesText(m.low) === minutesText(m.high) ? minutesText(m.low) : `${minutesText(m.low)} – ${minutesText(m.high)}`} on this machine` +
          ` (at most ${minutesText(m.cap)} if every phase runs to its step cap)`),
        ...(e.warnings || []).map(w => el('div', { class: 'estimate-warning' }, `⚠ ${w}`)));
    } catch (err) {
      if (seq !== estimateSeq) return;
      const field = err instanceof ProblemError ? err.problem.field : null;
      estimate.dataset.grains = '';
      estimate.replaceChildren(el('div', { class: 'error estimate-error' }, `This scheme would be refused: ${err.message}${field ? ` (${field})` : ''}`));
    }
  };
  const scheduleEstimate = () => { clearTimeout(estimateTimer); estimateTimer = setTimeout(runEstimate, 400); };
  form.addEventListener('input', scheduleEstimate);
  form.addEventListener('change', scheduleEstimate);
  form.addEventListener('click', ev => { if (ev.target.matches('.add-item, .remove-item')) scheduleEstimate(); });

  const pick = name => {
    const preset = presets.find(x => x.name === name);
    if (!preset) return;
    for (const b of presetBox.querySelectorAll('button')) {
      b.classList.toggle('active', b.dataset.preset === name);
      b.setAttribute('aria-pressed', String(b.dataset.preset === name));
    }
    schemeForm.load(preset.scheme);
    formError.textContent = '';
    runEstimate();
  };
  presetBox.replaceChildren(...presets.map(p => presetCard(p, pick)));
  if (presets.length) pick(presets[0].name);

  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    schemeForm.clearErrors();
    formError.textContent = '';
    submit.disabled = true;
    try {
      // The scheme carries its own `threads`; the request needs nothing else.
      const res = await postJSON('/runs', { scheme: schemeForm.scheme() });
      location.hash = `#/runs/${res.id}`;
    } catch (e) {
      const field = e instanceof ProblemError ? e.problem.field : null;
      // A pointer into the request body: the form holds the scheme, so drop "/scheme".
      const pointer = field ? field.replace(/^\/scheme(?=\/|$)/, '') : null;
      if (pointer != null) schemeForm.showError(pointer, e.message);
      formError.textContent = `${e.status ? e.status + ' ' : ''}${e.problem?.title || 'error'}: ${e.message}${field ? ` (${field})` : ''}`;
    } finally { submit.disabled = false; }
  });
  return { close() { clearTimeout(estimateTimer); } };
}

// ---- Runs list -------------------------------------------------------------------------

function showRuns() {
  const table = el('table', { class: 'grid', id: 'runs-table' });
  const scroller = el('div', { class: 'table-scroll' }, table);
  const error = el('div', { class: 'field-error' });
  const more = el('div', { class: 'row' });
  main.replaceChildren(el('h2', {}, 'Runs'), scroller, more, error);
  let timer = null, wanted = PAGE;
  const refresh = async () => {
    clearTimeout(timer);
    try {
      const { items: runs, total } = await getList('/runs', 'runs', wanted);
      more.replaceChildren(moreButton('runs-more', runs.length, total, () => { wanted += PAGE; refresh(); }));
      table.replaceChildren(
        el('tr', {}, ['id', 'name', 'status (why it failed)', 'progress (stage · % · ETA)', 'created', ''].map(h => el('th', {}, h))),
        ...runs.map(r => el('tr', { dataset: { runId: r.id } },
          el('td', {}, el('a', { href: `#/runs/${r.id}` }, `#${r.id}`)),
          el('td', {}, r.name || ''),
          el('td', {}, el('span', { class: `status status-${r.status}` }, r.status),
            r.error ? el('div', { class: 'error run-error-cell' }, r.error) : null),
          el('td', {}, progressElement(r.stage, r.progress_pct, r.eta_s)),
          el('td', {}, r.created_at || ''),
          el('td', {}, (r.status === 'queued' || r.status === 'running')
            ? el('button', { type: 'button', 'aria-label': `cancel run #${r.id}`, onclick: () => postJSON(`/runs/${r.id}/cancel`).then(refresh) }, 'cancel')
            : el('button', { type: 'button', 'aria-label': `re-run run #${r.id}`, onclick: () => postJSON(`/runs/${r.id}/rerun`).then(refresh) }, 're-run')))));
      error.textContent = '';
    } catch (e) { error.textContent = e.message; }
    timer = setTimeout(refresh, 2000);
  };
  refresh();
  return { close() { clearTimeout(timer); } };
}

// ---- Activity line (progress of active runs on every page) ------------------------------

let activityTimer = null, activitySeq = 0;

// Polled every 2 s, and at once on every navigation so no page shows a stale line. The
// sequence number keeps a single polling chain when a navigation overlaps a poll.
async function pollActivity() {
  clearTimeout(activityTimer);
  const seq = ++activitySeq;
  try {
    // Only the active jobs, filtered by the server: one page holds them all (at most the
    // queue limit plus the workers), however long the history is.
    const active = '?status=queued,running&limit=500';
    const [{ runs }, { diagnoses }] = await Promise.all([getJSON(`/runs${active}`), getJSON(`/diagnoses${active}`).catch(() => ({ diagnoses: [] }))]);
    if (seq !== activitySeq) return;
    const isActive = x => x.status === 'running' || x.status === 'queued';
    const items = [
      ...runs.filter(isActive).map(r =>
        el('a', { href: `#/runs/${r.id}`, class: 'activity-item' }, `run #${r.id} ${r.status} `, progressElement(r.stage, r.progress_pct, r.eta_s))),
      ...(diagnoses || []).filter(isActive).map(d =>
        el('a', { href: '#/diagnose', class: 'activity-item' }, `diagnosis #${d.id} ${d.status} `, progressElement(d.stage, d.progress_pct, d.eta_s ?? progressEta(`diagnosis-${d.id}`, d.progress_pct)))),
    ];
    activity.replaceChildren(...(items.length ? items : [el('span', { class: 'hint' }, 'no active runs or diagnoses')]));
  } catch { activity.replaceChildren(el('span', { class: 'error' }, 'service unreachable')); }
  if (seq === activitySeq) activityTimer = setTimeout(pollActivity, 2000);
}

// ---- Router ----------------------------------------------------------------------------

async function route() {
  if (current && current.close) current.close();
  current = null;
  pollActivity();
  const hash = location.hash || '#/new';
  for (const a of document.querySelectorAll('nav a')) a.classList.toggle('active', hash.startsWith(a.getAttribute('href')));
  const m = hash.match(/^#\/runs\/(\d+)/);
  if (m) current = new RunView(main, Number(m[1]));
  else if (hash.startsWith('#/runs')) current = showRuns();
  else if (hash.startsWith('#/compare')) current = new CompareView(main);
  else if (hash.startsWith('#/diagnose')) current = new DiagnosisView(main);
  else current = await showNewRun();
}

window.addEventListener('hashchange', route);
// A view that sees a status change (e.g. the run page at `done`) refreshes the line at
// once instead of leaving it stale for up to one polling period.
window.addEventListener('triax-activity', () => pollActivity());
getJSON('/health').then(h => { document.getElementById('version').textContent = `triaxd ${h.version || ''}`; }).catch(() => {});
route();
