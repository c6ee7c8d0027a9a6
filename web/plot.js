// A small canvas plotter: axes with "nice" ticks, units in the axis labels, a legend,
// linear or logarithmic x axis, several series (model lines, lab markers) and exports
// (PNG through canvas.toBlob, CSV of exactly the plotted points).
// Written here rather than taken from npm because the page must work with no CDN and no
// build step, the needs are narrow (a few hundred lines), and owning it lets the browser
// test read point counts straight from the DOM (data-points on the canvas).

const PALETTE = ['#1f5fa8', '#c0392b', '#2e8b57', '#8e44ad', '#d68910', '#17808c', '#7f8c8d', '#b03a7a'];

// Round a raw tick step to 1, 2 or 5 times a power of ten so tick labels read cleanly.
export function niceStep(span, targetTicks) {
  if (!(span > 0) || !Number.isFinite(span)) return 1;
  const raw = span / Math.max(1, targetTicks);
  const mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const f = raw / mag;
  const nice = f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10;
  return nice * mag;
}

export function linearTicks(lo, hi, targetTicks = 6) {
  const step = niceStep(hi - lo, targetTicks);
  const first = Math.ceil(lo / step - 1e-9) * step;
  const ticks = [];
  for (let v = first; v <= hi + step * 1e-9; v += step) ticks.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return ticks;
}

// Decade ticks for a log axis; lo and hi are positive data values.
export function logTicks(lo, hi) {
  const ticks = [];
  for (let e = Math.floor(Math.log10(lo)); e <= Math.ceil(Math.log10(hi)); e++) ticks.push(Math.pow(10, e));
  return ticks;
}

function formatTick(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  // Shortest exponent form that still tells neighbouring ticks apart (1.25e+5, not 1e+5).
  if (a >= 1e5 || a < 1e-3) {
    // 1.25×10⁵ rather than 1.25e+5: the form a lab report uses.
    const [mant, exp] = Number(v.toPrecision(4)).toExponential().split('e');
    const sup = String(Number(exp)).replace(/[-0-9]/g, c => '⁻⁰¹²³⁴⁵⁶⁷⁸⁹'['-0123456789'.indexOf(c)]);
    return `${mant === '1' ? '' : mant === '-1' ? '-' : mant + '×'}10${sup}`;
  }
  return Number(v.toPrecision(6)).toString();
}

export class Plot {
  // options: {title, xLabel, yLabel, xLog, xLogAllowed, height}
  constructor(container, options) {
    this.options = Object.assign({ height: 300, xLog: false }, options);
    this.series = new Map(); // name -> {name, color, points: [[x, y]], style, dash}
    this.root = document.createElement('figure');
    this.root.className = 'plot';
    if (options.id) this.root.id = options.id;
    const bar = document.createElement('figcaption');
    const title = document.createElement('span');
    title.className = 'plot-title';
    title.textContent = this.options.title || '';
    bar.appendChild(title);
    const tools = document.createElement('span');
    tools.className = 'plot-tools';
    if (this.options.xLogAllowed) {
      const label = document.createElement('label');
      this.logBox = document.createElement('input');
      this.logBox.type = 'checkbox';
      this.logBox.className = 'plot-log';
      this.logBox.checked = !!this.options.xLog;
      this.logBox.addEventListener('change', () => { this.options.xLog = this.logBox.checked; this.render(); });
      label.append(this.logBox, ' log time');
      tools.appendChild(label);
    }
    const png = document.createElement('button');
    png.type = 'button'; png.className = 'plot-png'; png.textContent = 'PNG';
    png.addEventListener('click', () => this.downloadPNG());
    const csv = document.createElement('button');
    csv.type = 'button'; csv.className = 'plot-csv'; csv.textContent = 'CSV';
    csv.addEventListener('click', () => this.downloadCSV());
    tools.append(png, csv);
    bar.appendChild(tools);
    this.canvas = document.createElement('canvas');
    this.canvas.dataset.points = '0';
    this.root.append(bar, this.canvas);
    container.appendChild(this.root);
    this.pending = false;
    this.resizeObserver = new ResizeObserver(() => this.render());
    this.resizeObserver.observe(this.root);
  }

  clear() { this.series.clear(); this.scheduleRender(); }

  ensureSeries(name, style = {}) {
    let s = this.series.get(name);
    if (!s) {
      s = { name, color: style.color || PALETTE[this.series.size % PALETTE.length], points: [],
            style: style.style || 'line', dash: style.dash || null };
      this.series.set(name, s);
    }
    return s;
  }

  setSeries(name, points, style) { this.ensureSeries(name, style).points = points.slice(); this.scheduleRender(); }

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

  visiblePoints(s) {
    return this.options.xLog ? s.points.filter(p => p[0] > 0) : s.points;
  }

  bounds() {
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (const s of this.series.values()) {
      for (const [x, y] of this.visiblePoints(s)) {
        if (x < x0) x0 = x; if (x > x1) x1 = x;
        if (y < y0) y0 = y; if (y > y1) y1 = y;
      }
    }
    if (!Number.isFinite(x0)) return null;
    if (this.options.xLog) {
      if (x1 <= x0) { x0 /= 10; x1 *= 10; }
      x0 = Math.pow(10, Math.floor(Math.log10(x0)));
      x1 = Math.pow(10, Math.ceil(Math.log10(x1)));
    } else if (x1 - x0 < 1e-12) { x0 -= 1; x1 += 1; }
    else { const xpad = (x1 - x0) * 0.015; x0 -= xpad; x1 += xpad; } // keep edge markers whole
    if (y1 - y0 < 1e-12) { const d = Math.abs(y0) * 0.1 || 1; y0 -= d; y1 += d; }
    const ypad = (y1 - y0) * 0.05;
    return { x0, x1, y0: y0 - ypad, y1: y1 + ypad };
  }

  render() {
    const canvas = this.canvas;
    const style = getComputedStyle(this.root);
    const inner = this.root.clientWidth - parseFloat(style.paddingLeft || 0) - parseFloat(style.paddingRight || 0);
    const cssWidth = Math.max(200, Math.floor(inner) || 480);
    const cssHeight = this.options.height;
    const dpr = window.devicePixelRatio || 1;
    if (canvas.width !== Math.round(cssWidth * dpr) || canvas.height !== Math.round(cssHeight * dpr)) {
      canvas.width = Math.round(cssWidth * dpr);
      canvas.height = Math.round(cssHeight * dpr);
      canvas.style.width = cssWidth + 'px';
      canvas.style.height = cssHeight + 'px';
    }
    const ctx = canvas.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, cssWidth, cssHeight);
    canvas.dataset.points = String(this.pointCount());
    canvas.dataset.series = String(this.series.size);
    // Points drawn on the current axes (a log axis leaves out t <= 0).
    canvas.dataset.visible = String([...this.series.values()].reduce((n, s) => n + this.visiblePoints(s).length, 0));

    const m = { left: 64, right: 14, top: 12, bottom: 44 };
    const w = cssWidth - m.left - m.right, h = cssHeight - m.top - m.bottom;
    const b = this.bounds();
    ctx.font = '12px system-ui, sans-serif';
    ctx.strokeStyle = '#333';
    ctx.strokeRect(m.left, m.top, w, h);
    ctx.fillStyle = '#222';
    ctx.textAlign = 'center';
    ctx.fillText(this.options.xLabel || '', m.left + w / 2, cssHeight - 8);
    ctx.save();
    ctx.translate(14, m.top + h / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.fillText(this.options.yLabel || '', 0, 0);
    ctx.restore();
    if (!b) {
      ctx.fillStyle = '#888';
      ctx.fillText('waiting for data…', m.left + w / 2, m.top + h / 2);
      return;
    }
    const logx = this.options.xLog;
    const lx = v => Math.log10(v);
    const sx = logx
      ? v => m.left + (lx(v) - lx(b.x0)) / (lx(b.x1) - lx(b.x0)) * w
      : v => m.left + (v - b.x0) / (b.x1 - b.x0) * w;
    const sy = v => m.top + h - (v - b.y0) / (b.y1 - b.y0) * h;

    // Grid and tick labels.
    ctx.strokeStyle = '#e4e4e4';
    ctx.fillStyle = '#333';
    ctx.lineWidth = 1;
    const xt = logx ? logTicks(b.x0, b.x1) : linearTicks(b.x0, b.x1, Math.max(3, Math.floor(w / 90)));
    ctx.textAlign = 'center';
    for (const t of xt) {
      const px = sx(t);
      if (px < m.left - 0.5 || px > m.left + w + 0.5) continue;
      ctx.beginPath(); ctx.moveTo(px, m.top); ctx.lineTo(px, m.top + h); ctx.stroke();
      ctx.fillText(formatTick(t), px, m.top + h + 15);
    }
    const yt = linearTicks(b.y0, b.y1, Math.max(3, Math.floor(h / 50)));
    ctx.textAlign = 'right';
    for (const t of yt) {
      const py = sy(t);
      if (py < m.top - 0.5 || py > m.top + h + 0.5) continue;
      ctx.beginPath(); ctx.moveTo(m.left, py); ctx.lineTo(m.left + w, py); ctx.stroke();
      ctx.fillText(formatTick(t), m.left - 5, py + 4);
    }

    // Series, clipped to the frame.
    ctx.save();
    ctx.beginPath(); ctx.rect(m.left, m.top, w, h); ctx.clip();
    for (const s of this.series.values()) {
      const pts = this.visiblePoints(s);
      ctx.strokeStyle = s.color; ctx.fillStyle = s.color; ctx.lineWidth = 1.6;
      ctx.setLineDash(s.dash || []);
      if (s.style === 'points') {
        for (const [x, y] of pts) { ctx.beginPath(); ctx.arc(sx(x), sy(y), 2.5, 0, 2 * Math.PI); ctx.fill(); }
      } else {
        ctx.beginPath();
        pts.forEach(([x, y], i) => (i ? ctx.lineTo(sx(x), sy(y)) : ctx.moveTo(sx(x), sy(y))));
        ctx.stroke();
        if (pts.length === 1) { ctx.beginPath(); ctx.arc(sx(pts[0][0]), sy(pts[0][1]), 2, 0, 2 * Math.PI); ctx.fill(); }
      }
    }
    ctx.restore();
    ctx.setLineDash([]);

    // Legend in the frame corner that hides the fewest data points (a fixed corner hid
    // the start of the energy curves).
    if (this.series.size > 0) {
      const names = [...this.series.values()];
      const lw = Math.min(w - 10, 16 + Math.max(...names.map(s => ctx.measureText(s.name).width)) + 14);
      const lh = 16 * names.length + 6;
      const corners = [[m.left + 6, m.top + 6], [m.left + w - 6 - lw, m.top + 6],
        [m.left + w - 6 - lw, m.top + h - 6 - lh], [m.left + 6, m.top + h - 6 - lh]];
      const hidden = ([cx, cy]) => names.reduce((n, s) => n + this.visiblePoints(s).filter(([x, y]) => {
        const px = sx(x), py = sy(y);
        return px >= cx && px <= cx + lw && py >= cy && py <= cy + lh;
      }).length, 0);
      let [lx, ly] = corners[0], least = hidden(corners[0]);
      for (const c of corners.slice(1)) { const k = hidden(c); if (k < least) { least = k; [lx, ly] = c; } }
      ctx.fillStyle = 'rgba(255,255,255,0.85)';
      ctx.fillRect(lx, ly, lw, lh);
      ctx.textAlign = 'left';
      names.forEach((s, i) => {
        const y = ly + 14 + i * 16;
        ctx.strokeStyle = s.color; ctx.fillStyle = s.color;
        if (s.style === 'points') { ctx.beginPath(); ctx.arc(lx + 12, y - 4, 3, 0, 2 * Math.PI); ctx.fill(); }
        else { ctx.setLineDash(s.dash || []); ctx.beginPath(); ctx.moveTo(lx + 5, y - 4); ctx.lineTo(lx + 19, y - 4); ctx.stroke(); ctx.setLineDash([]); }
        ctx.fillStyle = '#222';
        ctx.fillText(s.name, lx + 24, y);
      });
    }
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

  downloadPNG() {
    this.render();
    this.canvas.toBlob(blob => blob && downloadBlob(blob, this.fileStem() + '.png'), 'image/png');
  }
}

export function downloadBlob(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url; a.download = name;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}
