# Outside suite, YADE side (bench/outside/README.md; never run by CI): one drained triaxial
# curve, or one multi-stage creep test, of a periodic cell of polydisperse spheres in YADE.
#   OUT_CFG='{"case":"dense","sigma3_kPa":100,...}' nice -n 19 yade -n -x bench/outside/yade_triax.py
# Keys (defaults below in CFG): sigma3_kPa, seed, grains, mu (test friction), mu_compact
# (friction during the isotropic consolidation: 0 dense, = mu loose), eta_roll / alpha_kr
# (rolling resistance of CohFrictMat, 0 = off), mode "shear" or "creep", and for creep
# q_peak_kPa, levels, creep_c (the friction's log-time decay per decade), steps_per_day.
# Writes OUT_DIR/<case>_<sigma3>kPa_shear.csv or _creep.csv and a .json with the run's checks.
#
# Signs: YADE's stresses are negative in compression; everything written here is
# compression positive (q = sigma_zz - (sigma_xx + sigma_yy)/2, volumetric strain from the
# cell volume, positive = contraction, axial strain engineering, from the cell's z length).
import json, math, os, sys, time
from yade import pack, utils

CFG = {"case": "dense", "sigma3_kPa": 100.0, "seed": 11, "grains": 2000, "mu": 0.5, "mu_compact": 0.0,
       "eta_roll": 0.0, "alpha_kr": 2.0, "mode": "shear", "max_strain": 0.15, "inertial_number": 2.5e-3,
       "young_Pa": 1.0e8, "poisson": 0.3, "density": 2650.0, "damping": 0.2, "damping_consolidation": 0.7,
       "q_peak_kPa": 0.0, "levels": [0.1, 0.4, 0.6, 0.8], "creep_c": 0.0, "t0_min": 1.0,
       "steps_per_day": 4000, "state": ""}
CFG.update(json.loads(os.environ.get("OUT_CFG", "{}")))
out_dir = os.environ.get("OUT_DIR", ".")
s3 = CFG["sigma3_kPa"] * 1e3
tag = "%s_%dkPa" % (CFG["case"], round(CFG["sigma3_kPa"]))
wall0 = time.time()
checks = {"cfg": CFG, "yade": yade.config.version}

# Gradation: a coarse fill's sieve curve scaled down (diameters 2-6 mm, by mass).
psd_d = [0.002, 0.003, 0.004, 0.005, 0.006]
psd_cum = [0.0, 0.15, 0.45, 0.80, 1.0]
rolling = CFG["eta_roll"] > 0.0
mat = O.materials.append(CohFrictMat(young=CFG["young_Pa"], poisson=CFG["poisson"], density=CFG["density"],
                                     frictionAngle=math.atan(CFG["mu_compact"]), isCohesive=False,
                                     momentRotationLaw=rolling, alphaKr=CFG["alpha_kr"],
                                     etaRoll=CFG["eta_roll"] if rolling else -1.0, label="grain"))

ctl = PeriTriaxController(label="ctl", dynCell=False, globUpdate=5, growDamping=0.25)
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D()], [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()],
                    [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True, label="law")]),
    ctl,
    NewtonIntegrator(damping=CFG["damping"], label="newton"),
]


def stress():
    """Compression-positive principal-axis stresses (the cell's axes) in Pa."""
    s = utils.getStress()
    return -s[0, 0], -s[1, 1], -s[2, 2]


def hold_lateral(s3, axial=None, gain=0.5):
    """Outer integral loop on the controller's goals. In the strain-controlled shear the
    PeriTriaxController held the lateral stress (getStress) about 19 % above its goal for the
    whole test (119 kPa for a 100 kPa goal, dense 100 kPa run): each reading moves the goal
    by `gain` times the measured error, so the lateral stress (and the axial one in the creep
    holds) is the lab's cell pressure and load."""
    sx, sy, sz = stress()
    g = ctl.goal
    gx = g[0] + gain * (sx - s3)
    gy = g[1] + gain * (sy - s3)
    gz = g[2] if axial is None else g[2] + gain * (sz - axial)
    ctl.goal = Vector3(gx, gy, gz)


def q_and_p():
    sx, sy, sz = stress()
    lat = 0.5 * (sx + sy)
    return sz - lat, lat


d_mean = 0.004


def moment_law_on_every_contact():
    """CohesionMoment applies its rolling and twisting moments only to cohesive contacts
    unless always_use_moment_law is set: without it the rolling cases' etaRoll did nothing
    (their curves equalled the plain ones). Set on the engines in use (a loaded state
    brings its own)."""
    for e in O.engines:
        if isinstance(e, InteractionLoop):
            for f in e.lawDispatcher.functors:
                if isinstance(f, Law2_ScGeom6D_CohFrictPhys_CohesionMoment):
                    f.always_use_moment_law = rolling


moment_law_on_every_contact()
if CFG["state"] and os.path.exists(CFG["state"]):
    O.load(CFG["state"])
    ctl = [e for e in O.engines if isinstance(e, PeriTriaxController)][0]
    moment_law_on_every_contact()
    checks["consolidation"] = json.load(open(CFG["state"] + ".json"))
else:
    # A cloud already at porosity ~0.59 (random sequential placement reaches it for this
    # gradation in under a second, sizes unscaled): the consolidation then has far less
    # to travel than from a dilute gas.
    L = 0.048
    O.periodic = True
    O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
    sp = pack.SpherePack()
    n = sp.makeCloud((0, 0, 0), (L, L, L), num=CFG["grains"], periodic=True, psdSizes=psd_d, psdCumm=psd_cum,
                     distributeMass=True, seed=CFG["seed"], porosity=0.57)
    sp.toSimulation(material=mat)
    O.dt = 0.7 * utils.PWaveTimeStep()
    # Isotropic consolidation at the compaction friction, fast (the gas has no contacts),
    # then the test friction and a relaxation at sigma3 until the unbalanced force is small.
    ctl.goal = Vector3(-s3, -s3, -s3)
    ctl.stressMask = 7
    ctl.maxStrainRate = Vector3(50.0, 50.0, 50.0)
    ctl.maxUnbalanced = 1e-9
    # Consolidation with PFC's usual local damping 0.7 (it only brings the packing to rest
    # sooner); the test itself runs at CFG["damping"].
    newton.damping = CFG["damping_consolidation"]
    steps = 0
    while True:
        O.run(1000, True)
        steps += 1000
        p = sum(stress()) / 3.0
        if steps % 5000 == 0:
            print("consolidation", steps, "p_kPa %.1f" % (p / 1e3), "unb %.3f" % utils.unbalancedForce(),
                  "cpu_s %.1f" % time.process_time(), flush=True)
        if abs(p - s3) < 0.02 * s3 and utils.unbalancedForce() < 0.02:
            break
        if steps >= 30000 and p > 0.8 * s3:
            break  # the relaxation below brings it to sigma3 (recorded: consolidation_steps = cap)
        if steps > 200000:
            raise RuntimeError("consolidation did not converge")
    utils.setContactFriction(math.atan(CFG["mu"]))
    ctl.maxStrainRate = Vector3(0.5, 0.5, 0.5)
    relax = 0
    while True:
        O.run(1000, True)
        relax += 1000
        p = sum(stress()) / 3.0
        if (abs(p - s3) < 0.01 * s3 and utils.unbalancedForce() < 0.01) or relax >= 15000:
            break
    newton.damping = CFG["damping"]
    vs = sum(4.0 / 3.0 * math.pi * b.shape.radius ** 3 for b in O.bodies)
    cons = {"grains": len(O.bodies), "dt_s": O.dt, "consolidation_steps": steps, "relax_steps": relax,
            "porosity": 1.0 - vs / O.cell.volume, "p_kPa": sum(stress()) / 3e3, "unbalanced": utils.unbalancedForce(),
            "coordination": utils.avgNumInteractions(), "cell_m": [O.cell.hSize[i, i] for i in range(3)]}
    checks["consolidation"] = cons
    if os.environ.get("SAVE_STATE"):
        O.save(os.environ["SAVE_STATE"])
        json.dump(cons, open(os.environ["SAVE_STATE"] + ".json", "w"))

# The shear rate from the inertial number I = rate d_mean sqrt(rho / sigma3): quasi-static
# for I << 1e-2 (GDR MiDi; 2.5e-3 used, a compromise with the run time). Density is not scaled: I per step does not depend on it.
rate = CFG["inertial_number"] / (d_mean * math.sqrt(CFG["density"] / s3))
Lz0 = O.cell.hSize[2, 2]
V0 = O.cell.volume
checks["strain_rate_per_s"] = rate
checks["strain_per_step"] = rate * O.dt


def eps_a():
    return (Lz0 - O.cell.hSize[2, 2]) / Lz0


def eps_v():
    return (V0 - O.cell.volume) / V0


if CFG["mode"] == "shear":
    ctl.stressMask = 3
    # The controller's strain is the log strain since the cell was made (the consolidation
    # already compressed z): the goal is 0.3 more compression than now, beyond 15 %.
    ctl.goal = Vector3(-s3, -s3, ctl.strain[2] - 0.3)
    ctl.maxStrainRate = Vector3(10 * rate, 10 * rate, rate)
    every = max(1, int(round(0.0005 / (rate * O.dt))))
    rows, unb = [], []
    q0, _ = q_and_p()
    rows.append((0.0, q0, 0.0, s3, utils.unbalancedForce()))
    while eps_a() < CFG["max_strain"]:
        O.run(every, True)
        hold_lateral(s3)
        q, lat = q_and_p()
        u = utils.unbalancedForce()
        unb.append(u)
        rows.append((eps_a(), q, eps_v(), lat, u))
        if len(rows) % 200 == 0:
            print("shear eps_a %.2f %% q %.1f kPa eps_v %.2f %% unb %.3f cpu_s %.0f" %
                  (100 * eps_a(), q / 1e3, 100 * eps_v(), u, time.process_time()), flush=True)
    path = os.path.join(out_dir, tag + "_shear.csv")
    with open(path, "w") as f:
        f.write("axial_strain_pct,q_kPa,volumetric_strain_pct,lateral_kPa,unbalanced\n")
        for e, q, v, lat, u in rows:
            f.write("%.5f,%.4f,%.5f,%.4f,%.5f\n" % (100 * e, q / 1e3, 100 * v, lat / 1e3, u))
    qs = [r[1] for r in rows]
    checks.update({"shear_steps": O.iter, "q_peak_kPa": max(qs) / 1e3,
                   "unbalanced_mean": sum(unb) / len(unb), "unbalanced_max": max(unb),
                   "lateral_kPa_min": min(r[3] for r in rows[1:]) / 1e3,
                   "lateral_kPa_max": max(r[3] for r in rows[1:]) / 1e3})
else:
    # Multi-stage creep at constant deviator. Stage k: the deviator is raised at the shear's
    # strain rate to S_k q_peak, then held for one physical day = steps_per_day steps
    # (physical time linear in steps, t = step * 86400 s / steps_per_day). The creep
    # mechanism: the contacts' friction decays with the log of the time since the stage's
    # load was applied, mu(t) = mu (1 - c log10(1 + t / t0)); a new load increment starts
    # the decay again.
    lab_min = [0, 0.5, 1, 2, 4, 8, 15, 30, 45] + [60 + 15 * i for i in range(93)]
    spd = CFG["steps_per_day"]
    mu0, c, t0 = CFG["mu"], CFG["creep_c"], CFG["t0_min"]
    rows, stage_info = [], []
    ctl.stressMask = 7
    ctl.maxStrainRate = Vector3(10 * rate, 10 * rate, rate)
    e_before = 0.0
    for k, S in enumerate(CFG["levels"]):
        qk = S * CFG["q_peak_kPa"] * 1e3
        utils.setContactFriction(math.atan(mu0))
        ctl.goal = Vector3(-s3, -s3, -(s3 + qk))
        ramp = 0
        while True:
            O.run(50, True)
            ramp += 50
            hold_lateral(s3)  # the axial goal is the ramp's own
            q, _ = q_and_p()
            if abs(q - qk) < 0.01 * qk + 200.0:
                break
            if ramp > 400000:
                raise RuntimeError("stage %d: deviator not reached" % (k + 1))
        print("stage", k + 1, "loaded after", ramp, "steps, cpu_s %.0f" % time.process_time(), flush=True)
        n0 = O.iter
        targets = [int(round(m / 1440.0 * spd)) for m in lab_min]
        done = 0
        qh = []
        while done < len(targets):
            n = O.iter - n0
            if n >= targets[done]:
                q, lat = q_and_p()
                qh.append(q)
                rows.append((k + 1, S, lab_min[done], eps_a() - e_before, q, eps_v(), lat))
                done += 1
                continue
            step = min(10, targets[done] - n)
            t_min = n / spd * 1440.0
            if c > 0:
                utils.setContactFriction(math.atan(mu0 * (1.0 - c * math.log10(1.0 + t_min / t0))))
            O.run(step, True)
            hold_lateral(s3, s3 + qk, 0.1)
        stage_info.append({"stage": k + 1, "S": S, "q_target_kPa": qk / 1e3, "ramp_steps": ramp,
                           "instant_pct": 100 * rows[-len(targets)][3], "end_pct": 100 * rows[-1][3],
                           "q_held_min_kPa": min(qh) / 1e3, "q_held_max_kPa": max(qh) / 1e3,
                           "unbalanced_end": utils.unbalancedForce()})
        e_before = eps_a()
    path = os.path.join(out_dir, tag + "_creep.csv")
    with open(path, "w") as f:
        f.write("stage,stress_level,time_min,axial_strain_pct,q_kPa,volumetric_strain_pct,lateral_kPa\n")
        for st, S, m, e, q, v, lat in rows:
            f.write("%d,%.2f,%.2f,%.6f,%.4f,%.6f,%.4f\n" % (st, S, m, 100 * e, q / 1e3, 100 * v, lat / 1e3))
    checks["stages"] = stage_info
checks["wall_s"] = time.time() - wall0
checks["steps"] = O.iter
json.dump(checks, open(os.path.join(out_dir, tag + "_" + CFG["mode"] + ".json"), "w"), indent=1)
print("DONE", tag, json.dumps(checks))
