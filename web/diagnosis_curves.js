// A diagnosis's curves, as a lab engineer checks a calibration: for every confining
// pressure σ3 of the lab, the lab readings (points), the calibrated base model (dashed)
// and the final model with the kept effects (solid), for q-εa, εv-εa and each creep stage
// on log time; around the final model, the noise-floor band: ± tolerance_nrmse × the lab
// curve's range, the misfit a right model would still show (a change of packing and the
// readings' noise, engine/diagnose/noise_floor.hpp). Model curves are the report's
// base_curves and final_curves (lab units, server/io/diagnosis_json.cpp); lab readings are
// GET /datasets/{id}'s. Nothing is refitted here.

import { el } from './api.js';
import { Chart } from './chart.js';
import { kpaText } from './envelope.js';

const samePressure = (a, b) => Math.abs(a - b) <= 0.02 * Math.max(Math.abs(a), Math.abs(b));
const zip = (xs, ys) => (xs && ys ? xs.map((x, i) => [x, ys[i]]) : []);

// Lab readings of one curve kind at σ3 (and stage) as [x, y] from the upload's columns.
function labPoints(dataset, kind, sigma3, stage, xName, yName) {
  for (const c of dataset?.data?.curves || []) {
    if (c.kind !== kind || !samePressure(Number(c.confining_kPa), sigma3) || (kind === 'creep' && c.stage !== stage)) continue;
    const xi = c.columns.indexOf(xName), yi = c.columns.indexOf(yName);
    if (xi < 0 || yi < 0) continue;
    return c.rows.filter(r => r[xi] != null && r[yi] != null).map(r => [Number(r[xi]), Number(r[yi])]);
  }
  return [];
}

const modelCurve = (list, kind, sigma3, stage) =>
  (list || []).find(c => c.kind === kind && samePressure(c.confining_kPa, sigma3) && (kind !== 'creep' || c.stage === stage));

// The lab's σ3 values in the order the report's curves carry them.
export function pressures(report) {
  const out = [];
  for (const c of [...(report.final_curves || []), ...(report.base_curves || [])])
    if (!out.some(p => samePressure(p, c.confining_kPa))) out.push(c.confining_kPa);
  return out;
}

// One figure: lab points, base (dashed), final (solid), the band around the final model.
function drawPanel(chart, lab, base, final, band) {
  if (lab.length) chart.setSeries('lab', lab, { style: 'points', color: '#c0392b' });
  if (base.length) chart.setSeries('calibrated base model', base, { color: '#7f8c8d', dash: [6, 4] });
  if (final.length) chart.setSeries('final model (kept effects)', final, { color: '#1f5fa8', width: 2.2 });
  if (final.length && lab.length && band > 0) {
    const ys = lab.map(p => p[1]), h = band * (Math.max(...ys) - Math.min(...ys));
    const label = `noise floor ±${Number((100 * band).toPrecision(2))} % of the lab range`;
    chart.setSeries(`${label} (upper)`, final.map(([x, y]) => [x, y + h]), { color: '#9ec1e8', width: 1 });
    chart.setSeries(`${label} (lower)`, final.map(([x, y]) => [x, y - h]), { color: '#9ec1e8', width: 1 });
    chart.root.dataset.band = String(h);
  }
  chart.root.dataset.lab = String(lab.length);
  chart.root.dataset.base = String(base.length);
  chart.root.dataset.final = String(final.length);
}

// Figures for every σ3 into `container`; returns the charts (to destroy on the next report).
export function renderDiagnosisCurves(container, report, dataset, conditions) {
  const band = report.noise_floor?.tolerance_nrmse || 0;
  const charts = [];
  const sections = [];
  for (const s3 of pressures(report)) {
    const grid = el('div', { class: 'plot-grid' });
    const section = el('section', { class: 'sigma3-curves', dataset: { sigma3: String(s3) } },
      el('h4', {}, `σ3 = ${kpaText(s3)}`), grid);
    sections.push(section);
    const tag = String(s3).replace(/\W/g, '_');
    const cond = () => `${conditions()} · σ3 ${kpaText(s3)}`;
    const shearBase = modelCurve(report.base_curves, 'shear', s3), shearFinal = modelCurve(report.final_curves, 'shear', s3);
    if (shearBase || shearFinal) {
      const q = new Chart(grid, { id: `diagnosis-q-${tag}`, title: `q vs εa at σ3 ${kpaText(s3)}`, xLabel: 'axial strain (%)', yLabel: 'q (kPa)', yFromZero: true, fileName: `diagnosis_q_${tag}`, conditions: cond });
      drawPanel(q, labPoints(dataset, 'shear', s3, 0, 'axial_strain_pct', 'q_kPa'),
        zip(shearBase?.axial_strain_pct, shearBase?.deviator_kPa), zip(shearFinal?.axial_strain_pct, shearFinal?.deviator_kPa), band);
      charts.push(q);
      if (shearFinal?.volumetric_strain_pct || shearBase?.volumetric_strain_pct) {
        const v = new Chart(grid, { id: `diagnosis-vol-${tag}`, title: `εv vs εa at σ3 ${kpaText(s3)} (contraction +)`, xLabel: 'axial strain (%)', yLabel: 'volumetric strain (%)', fileName: `diagnosis_vol_${tag}`, conditions: cond });
        drawPanel(v, labPoints(dataset, 'shear', s3, 0, 'axial_strain_pct', 'volumetric_strain_pct'),
          zip(shearBase?.axial_strain_pct, shearBase?.volumetric_strain_pct), zip(shearFinal?.axial_strain_pct, shearFinal?.volumetric_strain_pct), band);
        charts.push(v);
      }
    }
    const stages = [...new Set([...(report.final_curves || []), ...(report.base_curves || [])]
      .filter(c => c.kind === 'creep' && samePressure(c.confining_kPa, s3)).map(c => c.stage))].sort((a, b) => a - b);
    for (const k of stages) {
      const b = modelCurve(report.base_curves, 'creep', s3, k), f = modelCurve(report.final_curves, 'creep', s3, k);
      const byDeformation = !!(f?.axial_deformation_mm || b?.axial_deformation_mm);
      const yName = byDeformation ? 'axial_deformation_mm' : 'axial_strain_pct';
      const c = new Chart(grid, { id: `diagnosis-creep-${tag}-${k}`, title: `creep stage ${k} at σ3 ${kpaText(s3)}${f?.stress_level ? ` (S = ${f.stress_level})` : ''}, log time`,
        xLabel: 'time since stage start (min, log)', yLabel: byDeformation ? 'deformation since stage load (mm)' : 'axial strain since stage load (%)',
        xLog: true, xLogAllowed: true, fileName: `diagnosis_creep_${tag}_${k}`, conditions: cond });
      drawPanel(c, labPoints(dataset, 'creep', s3, k, 'time_min', yName), zip(b?.time_min, b?.[yName]), zip(f?.time_min, f?.[yName]), band);
      charts.push(c);
    }
  }
  container.replaceChildren(...(sections.length ? sections
    : [el('p', { class: 'hint' }, 'This report carries no model curves (a report stored before they were kept).')]));
  return charts;
}
