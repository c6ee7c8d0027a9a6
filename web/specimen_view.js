// The specimen in 3D (three.js, npm `three`, served by triaxd at /vendor/): the particle
// states the service stores at the end of each stage (GET /runs/{id}/snapshots, then
// GET /runs/{id}/snapshots/{stage}?format=json): grains as instanced spheres coloured by
// displacement, rotation or crushing, the membrane (toggle), the measurement spheres and
// the strong force chains as lines. Drawn on demand (a frame per camera move), so 5k
// particles orbit smoothly. The VTK download is the same snapshot as ParaView reads it.
// three.js is loaded only when this view opens.

import { el, getJSON } from './api.js';
import { specimenFrame } from './specimen_frame.js';

const COLOUR_BY = [
  ['displacement_mm', 'displacement (mm)'],
  ['rotation_rad', 'rotation (rad)'],
  ['crushed', 'crushed (yes/no)'],
];

// Blue (low) to red (high) through white: readable on the light background.
function ramp(THREE, t) {
  const c = new THREE.Color();
  t = Math.min(1, Math.max(0, t));
  if (t < 0.5) c.setRGB(0.15 + 1.4 * t, 0.35 + 1.1 * t, 0.85);
  else c.setRGB(0.9, 0.9 - 1.3 * (t - 0.5), 0.85 - 1.5 * (t - 0.5));
  return c;
}

export class SpecimenView {
  constructor(container, runId) {
    this.container = container;
    this.id = runId;
    this.closed = false;
    container.specimen = this; // the browser test times frames through the card
    this.build();
    this.load();
  }

  build() {
    this.stageSelect = el('select', { id: 'specimen-stage', 'aria-label': 'snapshot (end of stage)' });
    this.colourSelect = el('select', { id: 'specimen-colour', 'aria-label': 'colour the grains by' },
      COLOUR_BY.map(([k, t]) => el('option', { value: k }, t)));
    this.membraneBox = el('input', { type: 'checkbox', id: 'specimen-membrane', checked: true });
    this.chainsBox = el('input', { type: 'checkbox', id: 'specimen-chains', checked: true });
    this.spheresBox = el('input', { type: 'checkbox', id: 'specimen-spheres', checked: true });
    this.cutBox = el('input', { type: 'checkbox', id: 'specimen-cut' });
    this.vtkLink = el('a', { id: 'specimen-vtk', href: '#', download: '' }, 'VTK download');
    this.info = el('div', { class: 'hint', id: 'specimen-info', 'aria-live': 'polite' }, 'loading particle snapshots…');
    this.legend = el('div', { class: 'specimen-legend', id: 'specimen-legend' });
    this.canvasBox = el('div', { class: 'specimen-canvas', id: 'specimen-canvas-box', hidden: true });
    this.tools = null;
    this.container.replaceChildren(
      el('h3', {}, 'Specimen in 3D'),
      this.tools = el('div', { class: 'row toolbar', hidden: true },
        el('label', {}, 'snapshot ', this.stageSelect),
        el('label', {}, 'colour by ', this.colourSelect),
        el('label', {}, this.membraneBox, ' membrane'),
        el('label', {}, this.chainsBox, ' strong force chains'),
        el('label', {}, this.spheresBox, ' measurement spheres'),
        el('label', { title: 'hide the front half (x > 0): the inside of the specimen' }, this.cutBox, ' cut plane x = 0'),
        this.vtkLink),
      this.info, this.canvasBox, this.legend);
    this.stageSelect.addEventListener('change', () => this.show(this.stageSelect.value));
    this.colourSelect.addEventListener('change', () => this.paint());
    for (const b of [this.membraneBox, this.chainsBox, this.spheresBox, this.cutBox]) b.addEventListener('change', () => this.visibility());
  }

  async load() {
    let list;
    try {
      list = await getJSON(`/runs/${this.id}/snapshots`);
    } catch (e) {
      this.info.textContent = e.status === 404 ? 'This server stores no particle snapshots for this run.' : `snapshots: ${e.message}`;
      this.container.dataset.state = 'unavailable';
      return;
    }
    // {"run_id", "items": [{"stage": "shear", "grains", "membrane_particles", "contacts"}]}
    const snaps = Array.isArray(list) ? list : list.items || list.snapshots || [];
    if (!snaps.length) { this.info.textContent = 'No particle snapshot was stored for this run.'; this.container.dataset.state = 'empty'; return; }
    this.stageSelect.replaceChildren(...snaps.map(s => {
      const stage = s.stage ?? s;
      return el('option', { value: stage }, `${s.label || `end of ${stage}`}${s.grains != null ? ` (${s.grains} grains, ${s.contacts ?? '?'} contacts)` : ''}`);
    }));
    this.stageSelect.value = String(snaps[snaps.length - 1].stage ?? snaps[snaps.length - 1]);
    this.tools.hidden = false;
    this.canvasBox.hidden = false;
    this.show(this.stageSelect.value);
  }

  async ensureScene() {
    if (this.THREE) return;
    const THREE = this.THREE = await import('three');
    const { OrbitControls } = await import('three/addons/controls/OrbitControls.js');
    const renderer = this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    renderer.setClearColor(0xffffff);
    const canvas = renderer.domElement;
    canvas.setAttribute('role', 'img');
    canvas.setAttribute('aria-label', `run ${this.id}: the specimen's particles in 3D; drag to orbit, wheel to zoom`);
    canvas.id = 'specimen-canvas';
    this.canvasBox.replaceChildren(canvas);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.1, 10000);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, 2, 1.5);
    this.scene.add(sun);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.draw());
    this.resize = () => {
      const w = Math.max(200, this.canvasBox.clientWidth), h = Math.min(560, Math.max(260, Math.round(w * 0.75)));
      renderer.setSize(w, h);
      this.camera.aspect = w / h;
      this.camera.updateProjectionMatrix();
      this.draw();
    };
    this.resizeObserver = new ResizeObserver(this.resize);
    this.resizeObserver.observe(this.canvasBox);
    this.resize();
  }

  draw() {
    if (this.renderer && !this.pendingDraw) {
      this.pendingDraw = true;
      requestAnimationFrame(() => { this.pendingDraw = false; if (!this.closed) this.renderer.render(this.scene, this.camera); });
    }
  }

  async show(stage) {
    this.info.textContent = `loading snapshot ${stage}…`;
    const at = encodeURIComponent(stage);
    this.vtkLink.href = `/runs/${this.id}/snapshots/${at}?format=vtk`;
    this.vtkLink.setAttribute('download', `run${this.id}_stage${stage}.vtk`);
    let snap;
    try {
      [snap] = await Promise.all([getJSON(`/runs/${this.id}/snapshots/${at}?format=json`), this.ensureScene()]);
    } catch (e) { this.info.textContent = `snapshot ${stage}: ${e.message}`; return; }
    if (this.closed) return;
    this.snap = snap;
    this.buildMeshes();
    this.paint();
    this.visibility();
    this.container.dataset.state = 'shown';
  }

  buildMeshes() {
    const THREE = this.THREE, s = this.snap, p = s.particles;
    for (const o of this.objects || []) { this.scene.remove(o); o.geometry?.dispose(); o.material?.dispose(); }
    this.objects = [];
    const groups = s.groups || {};
    const membraneGroup = Object.entries(groups).find(([, n]) => /membrane/i.test(n))?.[0];
    const grainGroup = Object.entries(groups).find(([, n]) => /grain|soil/i.test(n))?.[0] ?? '0';
    const n = p.x_mm.length;
    const grains = [], membrane = [];
    for (let i = 0; i < n; i++) {
      const g = String(p.group[i]);
      if (membraneGroup != null && g === membraneGroup) membrane.push(i);
      else if (g === grainGroup || membraneGroup == null) grains.push(i);
    }
    this.grainIndex = grains;
    // Low-polygon spheres (12 x 8 segments, 192 triangles): 5k grains are one draw call of
    // about a million triangles; the membrane coarser still (8 x 6).
    const sphere = new THREE.SphereGeometry(1, 12, 8);
    const m = new THREE.Matrix4(), q = new THREE.Quaternion(), v = new THREE.Vector3(), sc = new THREE.Vector3();
    const place = (mesh, list) => list.forEach((i, k) => {
      const r = p.radius_mm[i];
      mesh.setMatrixAt(k, m.compose(v.set(p.x_mm[i], p.z_mm[i], p.y_mm[i]), q, sc.set(r, r, r)));
    });
    this.grainMesh = new THREE.InstancedMesh(sphere, new THREE.MeshLambertMaterial(), grains.length);
    place(this.grainMesh, grains);
    this.objects.push(this.grainMesh);
    if (membrane.length) {
      this.membraneMesh = new THREE.InstancedMesh(new THREE.SphereGeometry(1, 8, 6), new THREE.MeshLambertMaterial({ color: 0x8a9bb0, transparent: true, opacity: 0.25, depthWrite: false }), membrane.length);
      place(this.membraneMesh, membrane);
      this.objects.push(this.membraneMesh);
    } else this.membraneMesh = null;
    // Strong force chains: contacts whose normal force exceeds the mean by one standard
    // deviation (the strong network of Radjai et al. carries most of the load), as lines
    // between the centres, darker for larger forces.
    const c = s.contacts || { i: [], j: [], normal_force_N: [] };
    const f = c.normal_force_N || [];
    const mean = f.reduce((a, b) => a + b, 0) / Math.max(1, f.length);
    const sd = Math.sqrt(f.reduce((a, b) => a + (b - mean) ** 2, 0) / Math.max(1, f.length));
    const cut = mean + sd, fmax = Math.max(cut, ...f.slice(0, 200000));
    const pos = [], col = [];
    for (let k = 0; k < f.length; k++) {
      if (!(f[k] > cut)) continue;
      const a = c.i[k], b = c.j[k];
      pos.push(p.x_mm[a], p.z_mm[a], p.y_mm[a], p.x_mm[b], p.z_mm[b], p.y_mm[b]);
      const t = (f[k] - cut) / Math.max(1e-12, fmax - cut);
      const shade = 0.55 - 0.5 * t;
      col.push(0.9 * shade + 0.1, shade * 0.4, shade * 0.2, 0.9 * shade + 0.1, shade * 0.4, shade * 0.2);
    }
    this.chainCount = pos.length / 6;
    this.chainRange = [cut, fmax];
    const lg = new THREE.BufferGeometry();
    lg.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    lg.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
    this.chains = new THREE.LineSegments(lg, new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false, transparent: true, opacity: 0.9 }));
    this.chains.renderOrder = 2;
    this.objects.push(this.chains);
    this.measureGroup = new THREE.Group();
    for (const ms of s.measurement_spheres || []) {
      const [x, y, z] = ms.center_mm;
      const w = new THREE.LineSegments(new THREE.WireframeGeometry(new THREE.SphereGeometry(ms.radius_mm, 16, 10)),
        new THREE.LineBasicMaterial({ color: 0x2e8b57, depthTest: false, transparent: true, opacity: 0.8 }));
      w.position.set(x, z, y);
      w.renderOrder = 3;
      this.measureGroup.add(w);
    }
    this.objects.push(this.measureGroup);
    for (const o of this.objects) this.scene.add(o);
    // Frame the specimen (z up in the engine is y up on screen).
    let zmin = Infinity, zmax = -Infinity, rmax = 0;
    for (let i = 0; i < n; i++) {
      zmin = Math.min(zmin, p.z_mm[i]); zmax = Math.max(zmax, p.z_mm[i]);
      rmax = Math.max(rmax, Math.hypot(p.x_mm[i], p.y_mm[i]) + p.radius_mm[i]);
    }
    const hgt = zmax - zmin, cz = 0.5 * (zmin + zmax);
    // Platens, axis triad and scale bar around the grains (the grains' extent, in mm).
    let gzmin = Infinity, gzmax = -Infinity;
    for (const i of grains) { gzmin = Math.min(gzmin, p.z_mm[i] - p.radius_mm[i]); gzmax = Math.max(gzmax, p.z_mm[i] + p.radius_mm[i]); }
    const frame = specimenFrame(THREE, { zmin: gzmin, zmax: gzmax, rmax });
    this.scaleMm = frame.scaleMm;
    this.objects.push(frame.group);
    this.scene.add(frame.group);
    if (!this.framed) {
      // Far enough that the whole height fits the vertical field of view, with a margin.
      const fit = 1.15 * (0.5 * hgt) / Math.tan(0.5 * this.camera.fov * Math.PI / 180) + rmax;
      const dist = Math.max(3 * rmax, fit) / Math.SQRT2;
      this.camera.position.set(dist, cz + 0.25 * hgt, dist);
      this.controls.target.set(0, cz, 0);
      this.controls.update();
      this.framed = true;
    }
    this.info.textContent = `snapshot ${s.stage}: ${grains.length} grains, ${membrane.length} membrane particles, ` +
      `${f.length} contacts (${this.chainCount} strong, normal force > mean + 1 sd = ${cut.toFixed(1)} N), ` +
      `${(s.measurement_spheres || []).length} measurement spheres`;
    // Crushed grains are named in words: "colour by crushed" is one click away, a count is not.
    const crushed = grains.filter(i => p.crushed?.[i]).length;
    this.info.append(el('span', { id: 'specimen-crushed' }, crushed ? ` · ${crushed} of ${grains.length} grains crushed` : ' · no grain crushed'));
    this.container.dataset.crushed = String(crushed);
    this.container.dataset.grains = String(grains.length);
  }

  paint() {
    if (!this.snap || !this.grainMesh) return;
    const THREE = this.THREE, p = this.snap.particles, key = this.colourSelect.value;
    const values = this.grainIndex.map(i => {
      const v = p[key]?.[i];
      return key === 'crushed' ? (v ? 1 : 0) : Math.abs(Number(v) || 0);
    });
    const hi = key === 'crushed' ? 1 : Math.max(1e-12, ...values);
    values.forEach((v, k) => this.grainMesh.setColorAt(k, key === 'crushed' ? new THREE.Color(v ? 0xc0392b : 0xb8c4d0) : ramp(THREE, v / hi)));
    this.grainMesh.instanceColor.needsUpdate = true;
    const label = COLOUR_BY.find(([k]) => k === key)[1];
    this.legend.replaceChildren(key === 'crushed'
      ? el('span', {}, el('span', { class: 'swatch', style: 'background:#c0392b' }), ' crushed  ', el('span', { class: 'swatch', style: 'background:#b8c4d0' }), ' intact',
        ` (${values.filter(Boolean).length} of ${values.length} crushed)`)
      : el('span', {}, `${label}: `, el('span', { class: 'ramp' }), ` 0 … ${Number(hi.toPrecision(3))}`),
      el('span', { id: 'specimen-frame-legend' }, ` · force chains light → dark red: ${Number(this.chainRange[0].toPrecision(3))} … ${Number(this.chainRange[1].toPrecision(3))} N` +
        ` · platens grey · axes x red, y green, z (axial) blue · scale bar ${this.scaleMm} mm`));
    this.draw();
  }

  visibility() {
    if (!this.snap) return;
    if (this.membraneMesh) this.membraneMesh.visible = this.membraneBox.checked;
    this.chains.visible = this.chainsBox.checked;
    this.measureGroup.visible = this.spheresBox.checked;
    // The cut plane keeps x <= 0 (three.js keeps what lies on the normal's side).
    this.renderer.clippingPlanes = this.cutBox.checked ? [new this.THREE.Plane(new this.THREE.Vector3(-1, 0, 0), 0)] : [];
    this.draw();
  }

  close() {
    this.closed = true;
    this.resizeObserver?.disconnect();
    this.controls?.dispose();
    this.renderer?.dispose();
  }
}
