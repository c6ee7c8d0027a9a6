// Thin client for the triaxd REST API (docs/api.md). Errors come back as RFC 7807
// problem details; they are thrown as ProblemError so callers can place the message
// beside the field named by its JSON pointer (`field`) or the file line (`line`).

export class ProblemError extends Error {
  constructor(status, problem) {
    super(problem.detail || problem.title || `HTTP ${status}`);
    this.status = status;
    this.problem = problem;
  }
}

async function parse(response) {
  const type = response.headers.get('Content-Type') || '';
  const body = type.includes('json') ? await response.json().catch(() => ({})) : await response.text();
  if (!response.ok) {
    const problem = typeof body === 'object' ? body : { title: response.statusText, detail: String(body).slice(0, 300) };
    throw new ProblemError(response.status, problem);
  }
  return body;
}

export async function getJSON(url) { return parse(await fetch(url, { headers: { Accept: 'application/json' } })); }

export async function postJSON(url, body) {
  return parse(await fetch(url, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', Accept: 'application/json' },
    body: JSON.stringify(body ?? {}),
  }));
}

export async function postRaw(url, body, contentType) {
  return parse(await fetch(url, { method: 'POST', headers: { 'Content-Type': contentType }, body }));
}

export async function del(url) { return parse(await fetch(url, { method: 'DELETE' })); }

// The unit is the suffix of every lab-facing field name; the label shows it once.
const UNITS = [
  ['_pct_per_min', '%/min'], ['_per_s', '1/s'], ['_per_min', '1/min'], ['_g_cm3', 'g/cm³'], ['_pct_min', '%/min'], ['_mm_min', 'mm/min'], ['_kPa_min', 'kPa/min'], ['_kPa_s', 'kPa/s'], ['_mm_s', 'mm/s'], ['_m_s', 'm/s'],
  ['_kPa', 'kPa'], ['_MPa', 'MPa'], ['_GPa', 'GPa'], ['_Pa', 'Pa'], ['_mm3', 'mm³'], ['_mm', 'mm'],
  ['_pct', '%'], ['_um', 'µm'], ['_min', 'min'], ['_s', 's'], ['_J', 'J'], ['_kg_m3', 'kg/m³'], ['_N_m', 'N/m'], ['_m', 'm'],
  ['_N', 'N'], ['_deg', '°'], ['_rad_s', 'rad/s'], ['_1_s', '1/s'],
];

// Longest suffix first, so `_rad_s` wins over `_s` and `_N_m` over `_m`.
UNITS.sort((a, b) => b[0].length - a[0].length);

export function splitUnit(name) {
  for (const [suffix, unit] of UNITS) {
    if (name.endsWith(suffix)) return { base: name.slice(0, -suffix.length), unit };
  }
  return { base: name, unit: '' };
}

export function axisLabel(column) {
  const { base, unit } = splitUnit(column);
  const words = base.replace(/_/g, ' ');
  return unit ? `${words} (${unit})` : words;
}

export function formatEta(seconds) {
  // Unknown ETA arrives as null or a negative number.
  if (seconds == null || !Number.isFinite(Number(seconds)) || Number(seconds) < 0) return '—';
  let s = Math.max(0, Math.round(Number(seconds)));
  if (s < 60) return `${s} s`;
  const h = Math.floor(s / 3600); s -= h * 3600;
  const m = Math.floor(s / 60); s -= m * 60;
  return h ? `${h} h ${m} min` : `${m} min ${s} s`;
}

// ETA (s) of work whose service reports no ETA (a diagnosis), from its progress as this
// page sees it: the mean rate since the page first saw it (a rate over the last sample
// swings with each step of uneven work: 12, 19, then 1.3 min). One estimate per key for
// the whole page, so the header's activity line and the view say the same. null until
// 5 s and 0.5 % have passed.
const progressSeen = new Map();
export function progressEta(key, pct) {
  const now = performance.now() / 1000, p = Number(pct);
  if (!Number.isFinite(p)) return null;
  const first = progressSeen.get(key);
  if (!first || p < first.p0) { progressSeen.set(key, { t0: now, p0: p }); return null; }
  const dp = p - first.p0, dt = now - first.t0;
  return dp > 0.5 && dt > 5 ? (100 - p) * dt / dp : null;
}

// A progress cell used everywhere long work appears: stage, bar with %, ETA.
export function progressElement(stage, pct, eta) {
  const wrap = document.createElement('span');
  wrap.className = 'progress';
  const p = Number.isFinite(Number(pct)) ? Number(pct) : 0;
  const bar = document.createElement('progress');
  bar.max = 100; bar.value = p;
  const text = document.createElement('span');
  text.className = 'progress-text';
  // Finished work has no ETA worth showing ("ETA 0 s" beside done reads as pending).
  text.textContent = `${stage ? stage + ' · ' : ''}${p.toFixed(1)} %${p >= 100 ? '' : ' · ETA ' + formatEta(eta)}`;
  wrap.append(bar, text);
  return wrap;
}

export function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v == null || v === false) continue;
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (k === 'dataset') Object.assign(e.dataset, v);
    else e.setAttribute(k, v === true ? '' : v);
  }
  for (const c of children.flat()) if (c != null) e.append(c instanceof Node ? c : String(c));
  return e;
}

// The list endpoints (GET /runs, /datasets, /comparisons, /diagnoses, /schemes) answer one
// page, newest first: `limit` items (server default 50, at most 500) before the cursor
// `before_id`. Reads pages until `count` items or the end of the list.
export const PAGE = 50;
export async function getList(path, key, count = PAGE) {
  const items = [];
  let before = null, total = 0;
  do {
    const q = new URLSearchParams({ limit: String(Math.min(500, count - items.length)) });
    if (before != null) q.set('before_id', String(before));
    const page = await getJSON(`${path}?${q}`);
    items.push(...(page[key] || []));
    total = page.total ?? items.length;
    before = page.next_before_id ?? null;
  } while (before != null && items.length < count);
  return { items, total, more: before != null };
}

// Every item of a list, in pages of 500: a picker must offer the oldest run or dataset too,
// not only the newest page.
export async function getAll(path, key) { return (await getList(path, key, Infinity)).items; }

// "more" under a paged table: shows how many of how many, and asks for one page more.
export function moreButton(id, shown, total, onclick) {
  return shown < total
    ? el('button', { type: 'button', class: 'more', id, onclick }, `more (${shown} of ${total} shown)`)
    : el('span', { class: 'hint', id }, total ? `all ${total} shown` : '');
}
