// The test-scheme form. It is generated from a preset scheme (GET /presets) with the
// JSON Schema (GET /schema/scheme) supplying limits, enums and descriptions, so a field
// added to the scheme on the server appears here without editing the page. Every input
// carries data-pointer = its JSON pointer; the server's 422 problem details name that
// pointer in `field`, and the message is shown beside that input.

import { el, splitUnit } from './api.js';

const escapeToken = t => String(t).replace(/~/g, '~0').replace(/\//g, '~1');

function resolveRef(schema, root) {
  let s = schema;
  for (let guard = 0; s && s.$ref && guard < 16; guard++) {
    const path = s.$ref.replace(/^#\/?/, '').split('/').filter(Boolean);
    s = path.reduce((node, key) => (node ? node[key.replace(/~1/g, '/').replace(/~0/g, '~')] : undefined), root);
  }
  if (s && Array.isArray(s.allOf)) s = Object.assign({}, ...s.allOf.map(x => resolveRef(x, root)), s);
  return s || {};
}

function childSchema(schema, key, root) {
  const s = resolveRef(schema, root);
  if (typeof key === 'number') return resolveRef(s.items || {}, root);
  return resolveRef((s.properties || {})[key] || {}, root);
}

function limitsText(s) {
  const parts = [];
  const lo = s.exclusiveMinimum ?? s.minimum, hi = s.exclusiveMaximum ?? s.maximum;
  if (lo != null && hi != null) parts.push(`${s.exclusiveMinimum != null ? '(' : '['}${lo} … ${hi}${s.exclusiveMaximum != null ? ')' : ']'}`);
  else if (lo != null) parts.push(`${s.exclusiveMinimum != null ? '>' : '≥'} ${lo}`);
  else if (hi != null) parts.push(`${s.exclusiveMaximum != null ? '<' : '≤'} ${hi}`);
  if (s.minItems != null || s.maxItems != null) parts.push(`${s.minItems ?? 0}…${s.maxItems ?? '∞'} items`);
  return parts.join(' ');
}

// Advisory only: the server remains the authority and its 422 is always shown.
function outOfRange(s, v) {
  if (typeof v !== 'number' || !Number.isFinite(v)) return false;
  if (s.minimum != null && v < s.minimum) return true;
  if (s.maximum != null && v > s.maximum) return true;
  if (s.exclusiveMinimum != null && v <= s.exclusiveMinimum) return true;
  if (s.exclusiveMaximum != null && v >= s.exclusiveMaximum) return true;
  return false;
}

// The service's JSON comes back with keys sorted alphabetically; show the scheme in the
// order a lab engineer fills it in: identity, specimen, grains, loading, then the model.
const SECTION_ORDER = ['name', 'seed', 'threads', 'max_particles', 'specimen', 'gradation', 'loading', 'micro', 'creep', 'effects'];

function orderedEntries(obj, pointer) {
  const entries = Object.entries(obj);
  const rank = ([k, v]) => {
    if (pointer === '') { const i = SECTION_ORDER.indexOf(k); return i < 0 ? SECTION_ORDER.length : i; }
    return v && typeof v === 'object' && !(Array.isArray(v) && !v.some(x => x && typeof x === 'object') && v.length) ? 1 : 0; // fields before sub-groups
  };
  return entries.map((e, i) => [e, i]).sort((a, b) => rank(a[0]) - rank(b[0]) || a[1] - b[1]).map(([e]) => e);
}

// The fields a lab engineer sets for a test, first and in these words (JSON pointer, label,
// hint); the rest of the scheme is the model and goes under "Advanced". A list here rather
// than a schema annotation: the page decides what it shows first, the schema what is valid.
export const ESSENTIAL = [
  ['/name', 'run name', null],
  ['/loading/confining_pressure_kPa', 'confining pressure σ3', null],
  ['/loading/stress_levels', 'creep stress levels S = q/q_f', 'one creep stage per level, each a share of the shear test\'s peak q'],
  ['/loading/stage_durations_min', 'creep stage durations', 'one per stage; 3600 min = 2.5 days'],
  ['/specimen/diameter_mm', 'specimen diameter', null],
  ['/specimen/height_mm', 'specimen height', null],
  ['/specimen/moisture_content_pct', 'moisture content w', null],
  ['/loading/max_axial_strain_pct', 'shear test up to axial strain', null],
  ['/max_particles', 'particle count (largest number of grains)', '0 = the full gradation; fewer grains are scaled up (faster, coarser)'],
];

// Strip binary floating-point noise (8.899999999999999 -> 8.9) for display only.
const tidy = v => (typeof v === 'number' && Number.isFinite(v) ? Number(v.toPrecision(12)) : v);

export class SchemeForm {
  constructor(container) {
    this.container = container;
    this.schema = {};
    this.value = {};
  }

  setSchema(schema) { this.schema = schema || {}; }

  load(scheme) {
    this.value = structuredClone(scheme);
    this.render();
  }

  scheme() { return structuredClone(this.value); }

  // The essential fields first, in the lab's words; every other field of the scheme (the
  // model's parameters) under "Advanced", generated from the JSON Schema as before.
  render() {
    const essential = el('fieldset', { class: 'group essential', id: 'essential-fields' }, el('legend', {}, 'The test'));
    const shown = new Set();
    for (const [pointer, label, hint] of ESSENTIAL) {
      const value = this.valueAt(pointer);
      if (value === undefined) continue;
      shown.add(pointer);
      const key = pointer.split('/').pop();
      const leaf = this.renderLeaf(value, this.schemaAt(pointer), pointer, key, label);
      if (hint) leaf.append(el('span', { class: 'hint' }, hint));
      essential.append(leaf);
    }
    const advancedTree = this.renderNode(this.value, this.schema, '', '', shown);
    const count = advancedTree.querySelectorAll('input, select').length;
    const advanced = el('details', { class: 'advanced', id: 'advanced-fields' },
      el('summary', {}, `Advanced: model parameters (${count} fields: grains, contacts, bonds, creep law, effects)`), advancedTree);
    advanced.open = this.advancedOpen || false;
    advanced.addEventListener('toggle', () => { this.advancedOpen = advanced.open; });
    this.container.replaceChildren(essential, advanced);
  }

  valueAt(pointer) {
    let node = this.value;
    for (const k of pointer.split('/').slice(1)) {
      if (node == null || typeof node !== 'object') return undefined;
      node = node[k.replace(/~1/g, '/').replace(/~0/g, '~')];
    }
    return node;
  }

  schemaAt(pointer) {
    let s = this.schema;
    for (const k of pointer.split('/').slice(1)) s = childSchema(s, k, this.schema);
    return resolveRef(s, this.schema);
  }

  setAt(pointer, v) {
    const keys = pointer.split('/').slice(1).map(k => k.replace(/~1/g, '/').replace(/~0/g, '~'));
    let node = this.value;
    for (let i = 0; i < keys.length - 1; i++) node = node[Array.isArray(node) ? Number(keys[i]) : keys[i]];
    const last = keys[keys.length - 1];
    node[Array.isArray(node) ? Number(last) : last] = v;
  }

  renderNode(value, schema, pointer, key, skip = new Set()) {
    const s = resolveRef(schema, this.schema);
    const itemSchema = resolveRef(s.items || {}, this.schema);
    const objectItems = itemSchema.type === 'object' || itemSchema.properties;
    if (Array.isArray(value) && (objectItems || value.some(v => v && typeof v === 'object'))) return this.renderObjectArray(value, s, pointer, key);
    if (value && typeof value === 'object' && !Array.isArray(value)) {
      const box = el('fieldset', { class: 'group', dataset: { pointer } });
      if (key !== '') box.append(el('legend', {}, String(key).replace(/_/g, ' ')));
      if (s.description && key !== '') box.append(el('p', { class: 'hint' }, s.description));
      for (const [k, v] of orderedEntries(value, pointer)) {
        const child = `${pointer}/${escapeToken(k)}`;
        if (skip.has(child)) continue;
        box.append(this.renderNode(v, childSchema(s, k, this.schema), child, k, skip));
      }
      return box;
    }
    return this.renderLeaf(value, s, pointer, String(key));
  }

  renderObjectArray(arr, s, pointer, key) {
    const box = el('fieldset', { class: 'group array', dataset: { pointer } });
    box.append(el('legend', {}, `${String(key).replace(/_/g, ' ')} (${arr.length})`));
    const lim = limitsText(s);
    if (lim) box.append(el('span', { class: 'limits' }, lim));
    arr.forEach((item, i) => {
      const inner = this.renderNode(item, childSchema(s, i, this.schema), `${pointer}/${i}`, `${key} ${i + 1}`);
      inner.append(el('button', { type: 'button', class: 'remove-item', onclick: () => { arr.splice(i, 1); this.render(); } }, 'remove'));
      box.append(inner);
    });
    // A new item copies the last one, or is built from the item schema's defaults.
    const fresh = () => {
      if (arr.length) return structuredClone(arr[arr.length - 1]);
      const props = resolveRef(s.items || {}, this.schema).properties || {};
      return Object.fromEntries(Object.entries(props).map(([k, p]) => {
        const ps = resolveRef(p, this.schema);
        return [k, ps.default ?? (ps.type === 'string' ? '' : ps.type === 'boolean' ? false : ps.minimum ?? 0)];
      }));
    };
    box.append(el('button', { type: 'button', class: 'add-item', onclick: () => { arr.push(fresh()); this.render(); } }, `add ${key}`));
    box.append(el('span', { class: 'field-error', role: 'alert' }));
    return box;
  }

  renderLeaf(value, s, pointer, key, labelText = null) {
    const { base, unit } = splitUnit(key);
    const id = 'f' + pointer.replace(/[^A-Za-z0-9]+/g, '_');
    const error = el('span', { class: 'field-error', role: 'alert' });
    // A list of numbers states the limits of each entry.
    const itemLimits = Array.isArray(value) ? limitsText(resolveRef(s.items || {}, this.schema)) : '';
    const limitText = [limitsText(s), itemLimits && `each ${itemLimits}`, Array.isArray(value) ? 'comma-separated' : ''].filter(Boolean).join(' ');
    const limits = el('span', { class: 'limits' }, limitText);
    let input;
    const type = Array.isArray(s.type) ? s.type.find(t => t !== 'null') : s.type;
    if (Array.isArray(s.enum)) {
      input = el('select', { id }, s.enum.map(o => el('option', { value: JSON.stringify(o), selected: o === value }, String(o))));
      input.addEventListener('change', () => this.setAt(pointer, JSON.parse(input.value)));
    } else if (typeof value === 'boolean' || type === 'boolean') {
      input = el('input', { id, type: 'checkbox', checked: !!value });
      input.addEventListener('change', () => this.setAt(pointer, input.checked));
    } else if (Array.isArray(value)) {
      input = el('input', { id, type: 'text', value: value.map(tidy).join(', ') });
      input.addEventListener('input', () => {
        const parts = input.value.split(',').map(t => t.trim()).filter(t => t !== '');
        this.setAt(pointer, parts.map(t => (Number.isFinite(Number(t)) ? Number(t) : t)));
      });
    } else if (typeof value === 'number' || type === 'number' || type === 'integer') {
      input = el('input', { id, type: 'number', step: 'any', value: tidy(value) ?? '', min: s.minimum ?? s.exclusiveMinimum, max: s.maximum ?? s.exclusiveMaximum });
      const check = () => {
        const raw = input.value.trim();
        const v = raw === '' ? null : Number(raw);
        this.setAt(pointer, v);
        const bad = v != null && outOfRange(s, v);
        input.classList.toggle('out-of-range', bad);
        input.parentElement?.classList.remove('has-error');
        error.textContent = bad ? `outside the limits ${limitsText(s)}` : '';
      };
      input.addEventListener('input', check);
    } else {
      input = el('input', { id, type: 'text', value: value ?? '' });
      input.addEventListener('input', () => this.setAt(pointer, input.value === '' && value === null ? null : input.value));
    }
    input.dataset.pointer = pointer;
    input.name = pointer;
    // A real number without a unit suffix is a ratio or coefficient: say so with (–), so
    // no number field leaves its unit to guesswork (integers are counts, no mark).
    const itemType = Array.isArray(value) ? resolveRef(s.items || {}, this.schema).type : null;
    const dimensionless = !unit && (type === 'number' || itemType === 'number' || (typeof value === 'number' && !Number.isInteger(value) && type !== 'integer'));
    const label = el('label', { for: id, title: s.description || pointer }, (labelText || base.replace(/_/g, ' ')) + (unit ? ` (${unit})` : dimensionless ? ' (–)' : ''));
    if (s.description) input.setAttribute('aria-description', s.description);
    return el('div', { class: 'field', dataset: { pointer } }, label, input, limits, error);
  }

  clearErrors() {
    for (const e of this.container.querySelectorAll('.field-error')) e.textContent = '';
    for (const e of this.container.querySelectorAll('.has-error')) e.classList.remove('has-error');
  }

  // Place the message beside the field named by the pointer, or the nearest enclosing
  // group when the pointer names a whole object or array. Returns false if nothing fits.
  showError(pointer, message) {
    let p = pointer || '';
    while (true) {
      const holder = [...this.container.querySelectorAll('[data-pointer]')]
        .find(e => e.dataset.pointer === p && (e.classList.contains('field') || e.classList.contains('group')));
      if (holder) {
        const details = holder.closest('details');
        if (details) details.open = true;
        const slot = holder.querySelector(':scope > .field-error') || holder.appendChild(el('span', { class: 'field-error', role: 'alert' }));
        slot.textContent = message;
        holder.classList.add('has-error');
        holder.scrollIntoView({ block: 'center', behavior: 'smooth' });
        holder.querySelector('input, select')?.focus({ preventScroll: true });
        return true;
      }
      if (p === '') return false;
      p = p.slice(0, p.lastIndexOf('/'));
    }
  }
}
