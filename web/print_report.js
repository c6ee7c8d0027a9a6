// A printable report of a run, a comparison or a diagnosis: the browser's own print (to
// paper or PDF) with the print rules of style.css (@media print: no navigation, forms or
// plot tools; plots at the page's width; cards not split). printHeader is the block that
// only the printout shows first: what is reported, the test conditions, the service's
// version, the date and the scheme as the run or diagnosis took it.

import { el } from './api.js';

export function printButton(id) {
  return el('button', { type: 'button', id, class: 'print-button', title: 'Print this report (or save it as PDF)', onclick: () => window.print() }, 'Print report');
}

// The scheme in a few words (lab units), then whole as JSON in small print.
const tidy = v => (typeof v === 'number' ? Number(v.toPrecision(10)) : v); // 8.899999999 -> 8.9

function schemeFacts(s) {
  if (!s) return [];
  const l = s.loading || {}, sp = s.specimen || {};
  const facts = [s.name && `scheme "${s.name}"`, l.confining_pressure_kPa != null && `σ3 ${tidy(l.confining_pressure_kPa)} kPa`,
    sp.moisture_content_pct != null && `w ${tidy(sp.moisture_content_pct)} %`,
    sp.diameter_mm != null && `specimen ${tidy(sp.diameter_mm)} × ${tidy(sp.height_mm)} mm`,
    l.stress_levels?.length && `stress levels ${l.stress_levels.join('/')}`,
    l.stage_durations_min?.length && `stage durations ${l.stage_durations_min.join('/')} min (model time)`,
    s.max_particles != null && `max ${s.max_particles} grains`, s.seed != null && `seed ${s.seed}`].filter(Boolean);
  return [el('p', {}, facts.join(' · ')), el('pre', { class: 'print-scheme' }, JSON.stringify(s))];
}

export function printHeader(title, conditions, scheme) {
  const version = document.getElementById('version')?.textContent || 'triaxd';
  return el('div', { class: 'print-only print-header' },
    el('h2', {}, title), el('p', {}, conditions),
    el('p', { class: 'hint' }, `${version} · printed ${new Date().toISOString().slice(0, 16).replace('T', ' ')} UTC`),
    ...schemeFacts(scheme));
}
