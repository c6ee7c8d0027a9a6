// What frames the specimen in the 3D view, as PFC3D draws it: the two platens (discs at the
// grains' top and bottom), an axis triad (x red, y green, z blue; z is the specimen's axis,
// drawn upwards) and a scale bar of a round length in mm beside the base. Scene units are
// mm; the engine's z is the scene's y (up on screen).

// A round length near a quarter of the specimen's diameter: 1, 2, 5 x 10^k mm.
export function scaleBarLength(diameterMm) {
  const target = Math.max(1e-3, diameterMm / 4), p = 10 ** Math.floor(Math.log10(target));
  return [1, 2, 5, 10].map(m => m * p).filter(v => v <= target).pop() || p;
}

// Returns {group, scaleMm}: the objects to add to the scene.
export function specimenFrame(THREE, { zmin, zmax, rmax }) {
  const group = new THREE.Group();
  const thick = Math.max(0.5, 0.03 * rmax);
  const platenMaterial = new THREE.MeshLambertMaterial({ color: 0x6b7785, transparent: true, opacity: 0.55 });
  for (const [z, side] of [[zmin, -1], [zmax, 1]]) {
    const disc = new THREE.Mesh(new THREE.CylinderGeometry(1.05 * rmax, 1.05 * rmax, thick, 48), platenMaterial);
    disc.position.set(0, z + side * thick / 2, 0);
    disc.name = side < 0 ? 'bottom platen' : 'top platen';
    group.add(disc);
  }
  // Axis triad at the bottom platen's edge; the specimen's z (axial) is the scene's y.
  const len = 0.45 * rmax, origin = new THREE.Vector3(-1.35 * rmax, zmin, 1.35 * rmax);
  for (const [dir, color] of [[[1, 0, 0], 0xc0392b], [[0, 0, 1], 0x2e8b57], [[0, 1, 0], 0x1f5fa8]])
    group.add(new THREE.ArrowHelper(new THREE.Vector3(...dir), origin, len, color, 0.2 * len, 0.1 * len));
  // Scale bar along x in front of the base, with end ticks; on the x < 0 side, which the
  // cut plane keeps (scaleMm <= rmax / 2, so the bar ends before x = 0).
  const scaleMm = scaleBarLength(2 * rmax);
  const y = zmin - 2 * thick, zf = 1.35 * rmax, x0 = -0.9 * rmax, tick = 0.06 * rmax;
  const pts = [x0, y, zf, x0 + scaleMm, y, zf, x0, y - tick, zf, x0, y + tick, zf, x0 + scaleMm, y - tick, zf, x0 + scaleMm, y + tick, zf];
  const bar = new THREE.BufferGeometry();
  bar.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
  group.add(new THREE.LineSegments(bar, new THREE.LineBasicMaterial({ color: 0x111111 })));
  return { group, scaleMm };
}
