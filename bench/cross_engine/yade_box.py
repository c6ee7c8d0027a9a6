# Cross-engine check, YADE side (bench/cross_engine/README.md; never run by CI). Reads the
# packing and the parameters that bench/cross_engine_box.cpp wrote and runs the same test:
# isotropic compression to sigma3 with friction 0.4, then drained shear to 10 % axial
# strain, walls on the same servo, the same linear law, local damping and time step.
#   XE_DIR=DIR yade -n -x bench/cross_engine/yade_box.py
# Writes DIR/yade_curve.csv (axial_strain_pct, q_kPa, volumetric_strain_pct, p_kPa).
#
# The law: ViscElMat with kn, ks given and cn = cs = 0 is the linear spring-slider with a
# constant stiffness (Law2_ScGeom_ViscElPhys_Basic); Ip2_ViscElMat_ViscElMat_ViscElPhys puts
# the two materials' springs in series, so each material gets 2 kn (checked on the first
# contact below). Walls: frictionless (the contact takes the smaller friction angle).
import json, math, os, sys
from yade import ymport, utils

d = os.environ["XE_DIR"]
P = json.load(open(os.path.join(d, "params.json")))
L = P["box_m"]
kn, ks = P["kn_N_m"], P["ks_N_m"]
grain = O.materials.append(ViscElMat(kn=2 * kn, ks=2 * ks, cn=0.0, cs=0.0, frictionAngle=math.atan(P["friction"]),
                                     density=P["density_kg_m3"]))
wallmat = O.materials.append(ViscElMat(kn=2 * kn, ks=2 * ks, cn=0.0, cs=0.0, frictionAngle=0.0,
                                       density=P["density_kg_m3"]))
spheres = ymport.text(os.path.join(d, "packing.txt"), material=grain)
O.bodies.append(spheres)
walls = []
for axis in range(3):
    walls.append(O.bodies.append(utils.wall(0.0, axis=axis, sense=1, material=wallmat)))
    walls.append(O.bodies.append(utils.wall(L[axis], axis=axis, sense=-1, material=wallmat)))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
                    [Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                    [Law2_ScGeom_ViscElPhys_Basic()]),
    NewtonIntegrator(damping=P["local_damping"], gravity=(0, 0, 0)),
]
O.dt = P["dt_s"]
sigma3 = P["sigma3_Pa"]

def lengths():
    return [O.bodies[walls[2 * a + 1]].state.pos[a] - O.bodies[walls[2 * a]].state.pos[a] for a in range(3)]

def wall_stress():
    l = lengths()
    area = [l[1] * l[2], l[0] * l[2], l[0] * l[1]]
    return [0.5 * (-O.forces.f(walls[2 * a])[a] + O.forces.f(walls[2 * a + 1])[a]) / area[a] for a in range(3)]

def servo(axes, gain, vmax):
    s = wall_stress()
    for a in axes:
        v = max(-vmax, min(vmax, gain * (s[a] - sigma3) / sigma3))
        lo, hi = Vector3(0, 0, 0), Vector3(0, 0, 0)
        lo[a], hi[a] = -v, v
        O.bodies[walls[2 * a]].state.vel = lo
        O.bodies[walls[2 * a + 1]].state.vel = hi

every = P["servo_every"]
O.step()
real = [i for i in O.interactions if i.isReal and i.id1 < len(spheres) and i.id2 < len(spheres)]
if real:
    k = real[0].phys.kn
    print("first grain contact: kn = %.6g N/m (target %.6g)" % (k, kn))
    if abs(k - kn) > 1e-6 * kn:
        sys.exit("the ViscElPhys stiffness is not the target: the series rule differs in this YADE")

# The servo runs inside the engine loop every `every` steps (as in triax), the samples too.
state = {"mode": "iso", "l0": None, "v0": None, "out": None}

def control():
    if state["mode"] == "iso":
        if O.iter < P["iso_steps"]:
            servo([0, 1, 2], P["servo_gain_m_s"], P["servo_vmax_m_s"])
            return
        s = wall_stress()
        l0 = lengths()
        v_solid = sum(4.0 / 3.0 * math.pi * b.shape.radius ** 3 for b in spheres)
        print("isotropic: stress %.2f %.2f %.2f kPa, solid fraction %.4f" % (s[0] * 1e-3, s[1] * 1e-3, s[2] * 1e-3,
                                                                            v_solid / (l0[0] * l0[1] * l0[2])))
        state.update(mode="shear", l0=l0, v0=l0[0] * l0[1] * l0[2], start=O.iter,
                     out=open(os.path.join(d, "yade_curve.csv"), "w"))
        state["out"].write("axial_strain_pct,q_kPa,volumetric_strain_pct,p_kPa\n")
        vz = 0.5 * P["strain_rate_per_s"] * l0[2]
        O.bodies[walls[4]].state.vel = Vector3(0, 0, vz)
        O.bodies[walls[5]].state.vel = Vector3(0, 0, -vz)
    l0, v0 = state["l0"], state["v0"]
    l = lengths()
    ea = (l0[2] - l[2]) / l0[2]
    if (O.iter - state["start"]) % P["sample_every"] == 0:
        s = wall_stress()
        q = s[2] - 0.5 * (s[0] + s[1])
        ev = (v0 - l[0] * l[1] * l[2]) / v0
        state["out"].write("%.6f,%.4f,%.6f,%.4f\n" % (100 * ea, 1e-3 * q, 100 * ev, 1e-3 * sum(s) / 3))
        state["out"].flush()
    if ea >= P["max_axial_strain"]:
        print("shear done")
        O.pause()
        return
    servo([0, 1], P["shear_servo_gain_m_s"], P["shear_servo_vmax_m_s"])

O.engines = O.engines + [PyRunner(command="control()", iterPeriod=every, initRun=True)]
O.run(-1, True)
