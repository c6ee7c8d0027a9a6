// Plots on uPlot (npm `uplot`, served by triaxd at /vendor/, docs/web.md): a figure with a
// title bar, the uPlot canvas (ticks, cursor with a hover readout in the legend, drag-box
// zoom, wheel zoom, shift- or middle-drag pan, double-click to reset), a legend whose
// entries toggle their series, a log-time switch, and PNG/CSV export. Series are kept as
// [x, y] points per series and joined on one sorted x column for uPlot's aligned data;
// each series' hover readout snaps to its own nearest point, so a lab marker and a model
// line are both read at the cursor.
//
// The figure carries data-points (all points), data-series and data-visible (points on the
// current axes: a log axis leaves out x <= 0), which the browser test reads.

import uPlot from '/vendor/uPlot.esm.js';

const PALETTE = ['#1f5fa8', '#c0392b', '#2e8b57', '#8e44ad', '#d68910', '#17808c', '#7f8c8d', '#b03a7a', '#4d6b00', '#a04000'];

// 1.25×10⁵ rather than 1.25e+5: the form a lab report uses; plain decimals otherwise.
// `power`: write v in powers of ten whatever its size (one axis in one form: not
// "50000, 10⁵, 1.5×10⁵" along the same axis).
export function formatTick(v, power = null) {
  if (v == null || !Number.isFinite(v)) return '';
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (power ?? (a >= 1e5 || a < 1e-3)) {
    const [mant, exp] = Number(v.toPrecision(4)).toExponential().split('e');
    const sup = String(Number(exp)).replace(/[-0-9]/g, c => '⁻⁰¹²³⁴⁵⁶⁷⁸⁹'['-0123456789'.indexOf(c)]);
    return `${mant === '1' ? '' : mant === '-1' ? '-' : mant + '×'}10${sup}`;
  }
  return String(Number(v.toPrecision(6)));
}

// Every tick of one axis in one form: powers of ten if any tick needs them.
export function formatTicks(vals) {
  const power = vals.some(v => v != null && v !== 0 && Number.isFinite(v) && (Math.abs(v) >= 1e5 || Math.abs(v) < 1e-3));
  return vals.map(v => formatTick(v, power));
}

const readout = v => (v == null || !Number.isFinite(v) ? '—' : formatTick(Number(v.toPrecision(4))));

export function downloadBlob(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url; a.download = name;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

// Wheel zooms x (and y with Alt) about the cursor; shift+drag or middle-drag pans.
function zoomPanPlugin(chart) {
  return {
    hooks: {
      ready: u => {
        const over = u.over;
        // uPlot's double-click shows everything again: live data then rescales as well.
        over.addEventListener('dblclick', () => { chart.zoomed = false; });
        over.addEventListener('wheel', e => {
          e.preventDefault();
          const f = e.deltaY < 0 ? 0.8 : 1.25;
          const zoomAxis = (key, pos) => {
            const s = u.scales[key];
            if (s.min == null) return;
            const at = u.posToVal(pos, key);
            const log = s.distr === 3;
            const t = v => (log ? Math.log10(v) : v), inv = v => (log ? 10 ** v : v);
            const c = t(at);
            u.setScale(key, { min: inv(c - (c - t(s.min)) * f), max: inv(c + (t(s.max) - c) * f) });
          };
          u.batch(() => {
            zoomAxis('x', u.cursor.left);
            if (e.altKey) zoomAxis('y', u.cursor.top);
          });
          chart.zoomed = true;
        }, { passive: false });
        over.addEventListener('mousedown', e => {
          if (!(e.button === 1 || (e.button === 0 && e.shiftKey))) return;
          e.preventDefault();
          e.stopPropagation();
          const x0 = e.clientX, y0 = e.clientY;
          const sx = { min: u.scales.x.min, max: u.scales.x.max }, sy = { min: u.scales.y.min, max: u.scales.y.max };
          const log = u.scales.x.distr === 3;
          const move = ev => {
            const dxPx = ev.clientX - x0, dyPx = ev.clientY - y0;
            const w = u.bbox.width / devicePixelRatio, h = u.bbox.height / devicePixelRatio;
            let nx;
            if (log) {
              const d = (Math.log10(sx.max) - Math.log10(sx.min)) * dxPx / w;
              nx = { min: 10 ** (Math.log10(sx.min) - d), max: 10 ** (Math.log10(sx.max) - d) };
            } else {
              const d = (sx.max - sx.min) * dxPx / w;
              nx = { min: sx.min - d, max: sx.max - d };
            }
            const dy = (sy.max - sy.min) * dyPx / h;
            u.batch(() => { u.setScale('x', nx); u.setScale('y', { min: sy.min + dy, max: sy.max + dy }); });
            chart.zoomed = true;
          };
          const up = () => { document.removeEventListener('mousemove', move); document.removeEventListener('mouseup', up); };
          document.addEventListener('mousemove', move);
          document.addEventListener('mouseup', up);
        }, true);
      },
    },
  };
}

export class Chart {
  // options: {id, title, xLabel, yLabel, xLog, xLogAllowed, yFromZero, fileName, height,
  //           conditions: () => string (test conditions printed on the exported PNG)}
  constructor(container, options) {
    this.options = Object.assign({ height: 280, xLog: false }, options);
    this.series = new Map(); // name -> {name, color, points: [[x, y]], style, dash}
    this.zoomed = false;
    this.u = null;
    this.shape = '';
    this.root = document.createElement('figure');
    this.root.className = 'plot';
    if (options.id) this.root.id = options.id;
    const titleId = `${options.id || 'plot' + Math.random().toString(36).slice(2)}-title`;
    this.root.setAttribute('aria-labelledby', titleId);
    const bar = document.createElement('figcaption');
    this.titleEl = document.createElement('span');
    this.titleEl.className = 'plot-title';
    this.titleEl.id = titleId;
    this.titleEl.textContent = this.options.title || '';
    bar.appendChild(this.titleEl);
    this.tools = document.createElement('span');
    this.tools.className = 'plot-tools';
    if (this.options.xLogAllowed) {
      const label = document.createElement('label');
      this.logBox = document.createElement('input');
      this.logBox.type = 'checkbox';
      this.logBox.className = 'plot-log';
      this.logBox.checked = !!this.options.xLog;
      this.logBox.addEventListener('change', () => { this.options.xLog = this.logBox.checked; this.zoomed = false; this.render(); });
      label.append(this.logBox, ' log time');
      this.tools.appendChild(label);
    }
    const button = (cls, text, title, fn) => {
      const b = document.createElement('button');
      b.type = 'button'; b.className = cls; b.textContent = text; b.title = title;
      b.setAttribute('aria-label', `${title}: ${this.options.title || ''}`);
      b.addEventListener('click', fn);
      this.tools.appendChild(b);
      return b;
    };
    button('plot-reset', 'reset', 'Reset zoom', () => { this.zoomed = false; this.render(true); });
    button('plot-png', 'PNG', 'Download as PNG', () => this.downloadPNG());
    button('plot-csv', 'CSV', 'Download the plotted points as CSV', () => this.downloadCSV());
    bar.appendChild(this.tools);
    this.body = document.createElement('div');
    this.body.className = 'plot-body';
    this.empty = document.createElement('div');
    this.empty.className = 'plot-empty hint';
    this.empty.textContent = 'waiting for data…';
    this.root.append(bar, this.body, this.empty);
    container.appendChild(this.root);
    this.root.chart = this; // the browser test reads the series and scales through the figure
    this.root.dataset.points = '0';
    this.root.dataset.series = '0';
    this.root.dataset.visible = '0';
    this.pending = false;
    this.resizeObserver = new ResizeObserver(() => {
      if (!this.u) return;
      this.u.setSize(this.size());
      // Equal scales hold at the new width only if y is ranged again.
      if (this.options.equalAspect) this.u.setData(this.u.data, true);
    });
    this.resizeObserver.observe(this.body);
  }

  setTitle(t) { this.options.title = t; this.titleEl.textContent = t; }

  // What the plot says while it has no point ("waiting for data…" by default).
  setEmptyText(t) { this.empty.textContent = t; }

  clear() { this.series.clear(); this.zoomed = false; this.scheduleRender(); }

  removeSeries(match) {
    for (const name of [...this.series.keys()]) if (match(name)) this.series.delete(name);
    this.scheduleRender();
  }

  ensureSeries(name, style = {}) {
    let s = this.series.get(name);
    if (!s) {
      const used = new Set([...this.series.values()].map(x => x.color));
      const color = style.color || PALETTE.find(c => !used.has(c)) || PALETTE[this.series.size % PALETTE.length];
      s = { name, color, points: [], style: style.style || 'line', dash: style.dash || null, width: style.width || 1.8 };
      this.series.set(name, s);
    }
    return s;
  }

  setSeries(name, points, style) {
    this.ensureSeries(name, style).points = points.filter(([x, y]) => Number.isFinite(x) && Number.isFinite(y));
    this.scheduleRender();
  }

  append(name, x, y, style) {
    if (!Number.isFinite(x) || !Number.isFinite(y)) return;
    this.ensureSeries(name, style).points.push([x, y]);
    this.scheduleRender();
  }

  pointCount() { let n = 0; for (const s of this.series.values()) n += s.points.length; return n; }

  // Many SSE events arrive per frame; draw at most once per animation frame.
  scheduleRender() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => { this.pending = false; this.render(); });
  }

  visiblePoints(s) { return this.options.xLog ? s.points.filter(p => p[0] > 0) : s.points; }

  size() {
    const w = Math.max(220, Math.floor(this.body.clientWidth || this.root.clientWidth - 12 || 480));
    return { width: w, height: this.options.height };
  }

  // uPlot's aligned data: the sorted union of every series' x, each series' y at its own
  // x and null elsewhere (drawn across with spanGaps).
  alignedData() {
    const list = [...this.series.values()];
    const xs = new Set();
    const pts = list.map(s => this.visiblePoints(s));
    for (const p of pts) for (const [x] of p) xs.add(x);
    const x = Float64Array.from(xs).sort();
    const index = new Map();
    x.forEach((v, i) => index.set(v, i));
    const ys = pts.map(p => {
      const y = new Array(x.length).fill(null);
      for (const [px, py] of p) y[index.get(px)] = py;
      return y;
    });
    return [Array.from(x), ...ys];
  }

  makeOptions() {
    const o = this.options;
    const list = [...this.series.values()];
    return {
      ...this.size(),
      plugins: [zoomPanPlugin(this)],
      hooks: { setSelect: [u => { if (u.select.width > 0) this.zoomed = true; }] },
      cursor: {
        drag: { x: true, y: true, uni: 20 },
        hover: { skip: [null, undefined], prox: Infinity },
        points: { size: 7 },
        focus: { prox: 16 },
      },
      focus: { alpha: 0.35 },
      legend: { live: true },
      scales: {
        // equalAspect (Mohr circles): x from 0, y from 0 with as many kPa per pixel as x.
        x: { time: false, distr: o.xLog ? 3 : 1, ...(o.equalAspect ? { range: (u, min, max) => [0, max > 0 ? max * 1.02 : 1] } : {}) },
        y: {
          range: (u, min, max) => {
            if (o.equalAspect) {
              // The plotting area is the figure less the y axis (70 px) and the x axis
              // (ticks and label, about 56 px); x spans [0, 1.02 x the largest x].
              const xs = u.data[0], xMax = xs.length ? xs[xs.length - 1] * 1.02 : 1;
              const w = this.size().width - 80, h = this.options.height - 56;
              return [0, xMax * h / Math.max(1, w)];
            }
            if (min == null || max == null) return [0, 1];
            if (o.yFromZero && min >= 0) min = 0;
            if (max - min < 1e-12) { const d = Math.abs(max) * 0.1 || 1; return [min - d, max + d]; }
            const pad = (max - min) * 0.05;
            return [o.yFromZero && min === 0 ? 0 : min - pad, max + pad];
          },
        },
      },
      axes: [
        { label: o.xLabel || '', values: (u, vals) => formatTicks(vals), grid: { stroke: '#e6e6e6' }, ticks: { stroke: '#999' },
          space: 60, labelSize: 26 },
        // size 70, labelSize 28: room for "deformation since stage load (mm)" and 5-digit ticks.
        { label: o.yLabel || '', values: (u, vals) => formatTicks(vals), grid: { stroke: '#e6e6e6' }, ticks: { stroke: '#999' },
          size: 70, labelSize: 28, labelFont: '12px system-ui, sans-serif' },
      ],
      series: [
        { label: o.xLabel || 'x', value: (u, v) => readout(v) },
        ...list.map(s => ({
          label: s.name,
          stroke: s.color,
          width: s.style === 'points' ? 0 : s.width,
          dash: s.dash || undefined,
          spanGaps: true,
          value: (u, v) => readout(v),
          points: s.style === 'points' ? { show: true, size: 6, fill: s.color, stroke: s.color } : { show: false },
          paths: s.style === 'points' ? () => null : undefined,
        })),
      ],
    };
  }

  render(resetZoom = false) {
    const list = [...this.series.values()];
    const total = this.pointCount();
    const visible = list.reduce((n, s) => n + this.visiblePoints(s).length, 0);
    this.root.dataset.points = String(total);
    this.root.dataset.series = String(list.length);
    this.root.dataset.visible = String(visible);
    this.empty.hidden = visible > 0;
    const shape = JSON.stringify([this.options.xLog, this.options.xLabel, this.options.yLabel,
      list.map(s => [s.name, s.color, s.style, s.dash])]);
    const data = this.alignedData();
    if (!this.u || shape !== this.shape) {
      if (this.u) this.u.destroy();
      this.shape = shape;
      this.zoomed = false;
      this.u = new uPlot(this.makeOptions(), data, this.body);
      this.u.over.tabIndex = -1;
      const canvas = this.u.root.querySelector('canvas');
      canvas.setAttribute('role', 'img');
      canvas.setAttribute('aria-label', `${this.options.title || 'plot'}: ${this.options.yLabel || 'y'} against ${this.options.xLabel || 'x'}` +
        (list.length ? `; series ${list.map(s => s.name).join(', ')}` : ''));
      return;
    }
    if (resetZoom) this.zoomed = false;
    this.u.setData(data, !this.zoomed);
  }

  // Long format so series of different lengths fit one file; headers carry the units
  // because the axis labels do.
  toCSV() {
    const q = v => (/[",\n]/.test(v) ? '"' + v.replace(/"/g, '""') + '"' : v);
    const lines = [['series', q(this.options.xLabel || 'x'), q(this.options.yLabel || 'y')].join(',')];
    for (const s of this.series.values()) for (const [x, y] of s.points) lines.push([q(s.name), x, y].join(','));
    return lines.join('\n') + '\n';
  }

  fileStem() { return (this.options.fileName || this.options.title || 'plot').replace(/[^A-Za-z0-9_-]+/g, '_'); }

  downloadCSV() { downloadBlob(new Blob([this.toCSV()], { type: 'text/csv' }), this.fileStem() + '.csv'); }

  // The plot canvas framed by its title, the test conditions and a legend: a figure that
  // can go into a report as it is.
  toPNG() {
    if (!this.u) this.render();
    const src = this.u.ctx.canvas;
    const dpr = src.width / Math.max(1, parseFloat(src.style.width) || src.width);
    const list = [...this.series.values()].filter((s, i) => this.u.series[i + 1]?.show !== false);
    const cols = Math.max(1, Math.floor(src.width / (dpr * 190)));
    const legendRows = Math.ceil(list.length / cols);
    // The conditions line wrapped at the canvas width (a phone-wide plot cut it off).
    const measure = document.createElement('canvas').getContext('2d');
    measure.font = '12px system-ui, sans-serif';
    const lines = [];
    for (const word of (this.options.conditions ? this.options.conditions() : '').split(' ')) {
      const last = lines.length ? lines[lines.length - 1] : null;
      if (last != null && measure.measureText(`${last} ${word}`).width <= src.width / dpr - 20) lines[lines.length - 1] = `${last} ${word}`;
      else lines.push(word);
    }
    const head = (34 + 16 * Math.max(1, lines.length)) * dpr, legend = (legendRows * 18 + 10) * dpr;
    const out = document.createElement('canvas');
    out.width = src.width;
    out.height = src.height + head + legend;
    this.root.dataset.pngConditionLines = String(lines.length);
    const ctx = out.getContext('2d');
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, out.width, out.height);
    ctx.scale(dpr, dpr);
    ctx.fillStyle = '#111';
    ctx.font = '600 15px system-ui, sans-serif';
    ctx.fillText(this.options.title || '', 10, 20);
    ctx.font = '12px system-ui, sans-serif';
    ctx.fillStyle = '#333';
    lines.forEach((line, i) => ctx.fillText(line, 10, 40 + 16 * i));
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(src, 0, head);
    ctx.scale(dpr, dpr);
    const top = (head + src.height) / dpr;
    list.forEach((s, i) => {
      const x = 10 + (i % cols) * 190, y = top + 14 + Math.floor(i / cols) * 18;
      ctx.strokeStyle = s.color; ctx.fillStyle = s.color; ctx.lineWidth = 2;
      if (s.style === 'points') { ctx.beginPath(); ctx.arc(x + 8, y - 4, 3, 0, 2 * Math.PI); ctx.fill(); }
      else { ctx.setLineDash(s.dash || []); ctx.beginPath(); ctx.moveTo(x, y - 4); ctx.lineTo(x + 16, y - 4); ctx.stroke(); ctx.setLineDash([]); }
      ctx.fillStyle = '#222';
      ctx.fillText(s.name, x + 22, y);
    });
    return out;
  }

  downloadPNG() {
    this.toPNG().toBlob(blob => blob && downloadBlob(blob, this.fileStem() + '.png'), 'image/png');
  }

  destroy() { this.resizeObserver.disconnect(); if (this.u) this.u.destroy(); }
}
