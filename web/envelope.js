// The strength envelope as a lab report gives it: the Mohr circle at failure (peak q) of
// each confining pressure and the Mohr-Coulomb line tau = c' + sigma' tan(phi'), drawn
// from the service's fit (GET /datasets/{id}/envelope, GET /runs/{id}/envelope,
// report.strength_envelope; server/io/strength_envelope_json.cpp, the engine's lab_macro).
// The page fits nothing itself: it draws and prints the API's numbers. Stresses in kPa,
// effective, compression positive; angles in degrees.

import { el } from './api.js';
import { Chart } from './chart.js';

// "50 kPa", "12.5 kPa": at most 4 significant digits, no trailing zeros.
export const kpaText = v => (v == null || !Number.isFinite(Number(v)) ? '—' : `${Number(Number(v).toPrecision(4))} kPa`);
const fixed = (v, d) => (v == null || !Number.isFinite(Number(v)) ? '—' : Number(v).toFixed(d));

// "c' = 20.0 kPa, φ' = 35.0°" (c' through the origin with one σ3 is said so).
export function envelopeText(e) {
  if (!e || e.friction_angle_deg == null) return 'no shear curve with a peak';
  const origin = e.n_pressures === 1 ? ' (one σ3: line through the origin)' : '';
  return `c' = ${fixed(e.cohesion_kPa, 1)} kPa, φ' = ${fixed(e.friction_angle_deg, 1)}°${origin}`;
}

// One row per source (lab, run, calibrated base, final model): σ3 set, q at failure, c', φ',
// and the line in p'-q (q = M p' + k).
export function envelopeTable(id, sets) {
  const head = ['source', 'σ3 (kPa)', 'q at failure (kPa)', "c' (kPa)", "φ' (°)", "p'-q line: M", 'k (kPa)'];
  return el('div', { class: 'table-scroll' }, el('table', { class: 'grid', id },
    el('tr', {}, head.map(h => el('th', {}, h))),
    sets.map(({ label, envelope: e }) => el('tr', { dataset: { source: label } },
      el('td', {}, label),
      el('td', {}, (e?.circles || []).map(c => Number(c.sigma3_kPa.toPrecision(4))).join(', ') || '—'),
      el('td', {}, (e?.circles || []).map(c => Number(c.q_peak_kPa.toPrecision(4))).join(', ') || '—'),
      el('td', { class: 'envelope-c' }, fixed(e?.cohesion_kPa, 1)),
      el('td', { class: 'envelope-phi' }, fixed(e?.friction_angle_deg, 1)),
      el('td', {}, fixed(e?.p_q_line?.slope, 3)),
      el('td', {}, fixed(e?.p_q_line?.intercept_kPa, 1))))));
}

// Upper half of the circle through sigma3 and sigma1 (x rises monotonically, as uPlot wants).
export function circlePoints(sigma3, sigma1, n = 48) {
  const c = (sigma1 + sigma3) / 2, r = (sigma1 - sigma3) / 2, pts = [];
  for (let i = 0; i <= n; i++) { const t = Math.PI * i / n; pts.push([c - r * Math.cos(t), r * Math.sin(t)]); }
  return pts;
}

const COLORS = ['#c0392b', '#1f5fa8', '#2e8b57', '#8e44ad'];

// Mohr circles and envelope lines of several sources on one τ-σ' plot, equal scales.
// sets: [{label, envelope, dash?}]
export function mohrChart(container, id, sets, conditions) {
  const chart = new Chart(container, { id, title: 'Mohr circles at failure and Mohr-Coulomb envelope', xLabel: "σ' (kPa)", yLabel: 'τ (kPa)',
    equalAspect: true, height: 300, fileName: id, conditions });
  drawMohr(chart, sets);
  return chart;
}

export function drawMohr(chart, sets) {
  chart.clear();
  let xmax = 0;
  for (const s of sets) for (const c of s.envelope?.circles || []) xmax = Math.max(xmax, c.sigma1_kPa);
  sets.forEach((s, k) => {
    const e = s.envelope, color = COLORS[k % COLORS.length];
    if (!e?.circles?.length) return;
    for (const c of e.circles)
      chart.setSeries(`${s.label} circle σ3 ${kpaText(c.sigma3_kPa)}`, circlePoints(c.sigma3_kPa, c.sigma1_kPa), { color, dash: s.dash, width: 1.4 });
    if (e.friction_angle_deg != null) {
      const tan = Math.tan(e.friction_angle_deg * Math.PI / 180), x1 = xmax * 1.05;
      chart.setSeries(`${s.label} envelope (${envelopeText(e).replace(/ \(one σ3.*\)$/, '')})`,
        [[0, e.cohesion_kPa], [x1, e.cohesion_kPa + tan * x1]], { color, dash: [8, 3], width: 2.2 });
    }
  });
  chart.root.dataset.circles = String(sets.reduce((n, s) => n + (s.envelope?.circles?.length || 0), 0));
}

// The peaks in p'-q (p' = σ3 + q/3 at failure) and each source's Mohr-Coulomb line there,
// q = M p' + k (the API's p_q_line), on one plot.
export function pqChart(container, id, sets, conditions) {
  const chart = new Chart(container, { id, title: "Failure in p'-q and the Mohr-Coulomb line", xLabel: "p' (kPa)", yLabel: 'q (kPa)',
    yFromZero: true, height: 300, fileName: id, conditions });
  drawPq(chart, sets);
  return chart;
}

export function drawPq(chart, sets) {
  chart.clear();
  let pMax = 0;
  for (const s of sets) for (const c of s.envelope?.circles || []) pMax = Math.max(pMax, c.p_kPa);
  sets.forEach((s, k) => {
    const e = s.envelope, color = COLORS[k % COLORS.length];
    if (!e?.circles?.length) return;
    chart.setSeries(`${s.label} failure (p', q)`, e.circles.map(c => [c.p_kPa, c.q_peak_kPa]), { style: 'points', color });
    if (e.p_q_line) {
      const x1 = pMax * 1.15;
      chart.setSeries(`${s.label} line q = ${e.p_q_line.slope.toFixed(3)} p' + ${e.p_q_line.intercept_kPa.toFixed(1)} kPa`,
        [[0, e.p_q_line.intercept_kPa], [x1, e.p_q_line.intercept_kPa + e.p_q_line.slope * x1]], { color, dash: s.dash || [8, 3] });
    }
  });
}
