#!/usr/bin/env python3
"""Packing preparation and conversion tools of the DEM throughput benchmark.

Sub-commands (all deterministic for a given seed):
  rsa        polydisperse random sequential addition of spheres in a walled box
             -> LAMMPS data file (atom_style sphere)
  template   12-sphere clump template inside an ellipsoid
             -> trackbed template CSV + LAMMPS molecule file
  rsa-clumps random sequential addition of randomly oriented clumps
             -> LAMMPS data file (atom_style sphere + fix property/atom mol)
  spheres    settled LAMMPS dump -> benchmark start state for both codes
             (LAMMPS data file with zero velocities, trackbed particle CSV)
  clumps     settled LAMMPS dump of clumps -> Kabsch fit of every body onto the
             template -> trackbed particle CSV (origin + quaternion) and LAMMPS
             data file rebuilt from the fitted poses (both codes get the very same
             member positions)
  summary    print the numbers of a LAMMPS log (Loop time of the last run, CHECK line)

Only numpy is needed (Debian python3-numpy).
"""
import argparse
import math
import re
import sys

import numpy as np

FMT = "%.17g"


# --------------------------------------------------------------------------- helpers
class CellGrid:
    """Uniform cell list for overlap queries during sequential addition."""

    def __init__(self, lo, hi, h):
        self.lo = np.asarray(lo, float)
        self.h = float(h)
        self.n = np.maximum(1, np.ceil((np.asarray(hi, float) - self.lo) / h).astype(int))
        self.cells = {}
        self.pos = []
        self.rad = []

    def _key(self, p):
        c = np.floor((p - self.lo) / self.h).astype(int)
        return tuple(np.clip(c, 0, self.n - 1))

    def neighbours(self, p):
        cx, cy, cz = self._key(p)
        out = []
        for i in (cx - 1, cx, cx + 1):
            for j in (cy - 1, cy, cy + 1):
                for k in (cz - 1, cz, cz + 1):
                    lst = self.cells.get((i, j, k))
                    if lst:
                        out.extend(lst)
        return out

    def fits(self, pts, rads):
        """True if spheres (pts[m,3], rads[m]) overlap none of the stored ones."""
        for p, r in zip(pts, rads):
            idx = self.neighbours(p)
            if not idx:
                continue
            q = self.P[idx]
            d2 = np.sum((q - p) ** 2, axis=1)
            if np.any(d2 < (self.R[idx] + r) ** 2):
                return False
        return True

    def reserve(self, n):
        self.P = np.zeros((n, 3))
        self.R = np.zeros(n)
        self.count = 0

    def add(self, pts, rads):
        for p, r in zip(pts, rads):
            self.P[self.count] = p
            self.R[self.count] = r
            self.cells.setdefault(self._key(p), []).append(self.count)
            self.count += 1


def random_quaternion(rng):
    """Uniformly distributed unit quaternion (Shoemake)."""
    u1, u2, u3 = rng.random(3)
    a, b = math.sqrt(1 - u1), math.sqrt(u1)
    return np.array([a * math.sin(2 * math.pi * u2), a * math.cos(2 * math.pi * u2),
                     b * math.sin(2 * math.pi * u3), b * math.cos(2 * math.pi * u3)])


def quat_to_matrix(q):
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def matrix_to_quat(R):
    """Unit quaternion (w,x,y,z), w >= 0, of a proper rotation matrix."""
    t = np.trace(R)
    if t > 0:
        s = math.sqrt(t + 1.0) * 2
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2]) * 2
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif R[1, 1] > R[2, 2]:
        s = math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2]) * 2
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1]) * 2
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    q /= np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def read_template_csv(path):
    a = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return a[:, :3], a[:, 3]


def read_dump(path):
    """Last snapshot of a LAMMPS custom text dump -> dict column -> array, sorted by id."""
    with open(path) as f:
        lines = f.read().splitlines()
    starts = [i for i, l in enumerate(lines) if l.startswith("ITEM: TIMESTEP")]
    s = starts[-1]
    n = int(lines[s + 3])
    box = [tuple(map(float, lines[s + 5 + k].split()[:2])) for k in range(3)]
    cols = lines[s + 8].split()[2:]
    data = np.array([l.split() for l in lines[s + 9:s + 9 + n]], dtype=float)
    d = {c: data[:, k] for k, c in enumerate(cols)}
    order = np.argsort(d["id"])
    d = {c: v[order] for c, v in d.items()}
    d["_box"] = box
    d["_step"] = int(lines[s + 1])
    return d


def write_lammps_data(path, pos, diam, dens, box, mol=None, title="trackbed bench"):
    n = len(pos)
    with open(path, "w") as f:
        f.write(f"LAMMPS data file: {title}\n\n{n} atoms\n1 atom types\n\n")
        for k, ax in enumerate("xyz"):
            f.write(f"{box[k][0]!r} {box[k][1]!r} {ax}lo {ax}hi\n")
        f.write("\nAtoms # sphere\n\n")
        for i in range(n):
            f.write("%d 1 %s %s %s %s %s\n" % (i + 1, FMT % diam[i], FMT % dens,
                                              FMT % pos[i, 0], FMT % pos[i, 1], FMT % pos[i, 2]))
        if mol is not None:
            f.write("\nMolecules\n\n")
            for i in range(n):
                f.write("%d %d\n" % (i + 1, mol[i]))


def sphere_diameters(n, dmin, dmax, rng):
    return rng.uniform(dmin, dmax, n)


def union_mass_properties(cen, rad, h=1e-4):
    """Volume, centroid and inertia tensor (about the centroid, per unit density) of the UNION
    of spheres, by midpoint integration on a grid of spacing h (relative error ~1e-4 at 0.1 mm
    for these 10 mm spheres).  LAMMPS would otherwise sum the member spheres (overlaps twice)."""
    lo = np.min(cen - rad[:, None], axis=0)
    hi = np.max(cen + rad[:, None], axis=0)
    xs = np.arange(lo[0] + h / 2, hi[0], h)
    ys = np.arange(lo[1] + h / 2, hi[1], h)
    zs = np.arange(lo[2] + h / 2, hi[2], h)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    dxy2 = [(X - c[0]) ** 2 + (Y - c[1]) ** 2 for c in cen]
    S = np.zeros(10)   # 1, x, y, z, xx, yy, zz, xy, xz, yz
    for z in zs:
        m = np.zeros(X.shape, bool)
        for k, c in enumerate(cen):
            r2 = rad[k] ** 2 - (z - c[2]) ** 2
            if r2 > 0:
                m |= dxy2[k] < r2
        if not m.any():
            continue
        x, y = X[m], Y[m]
        n = x.size
        S += [n, x.sum(), y.sum(), n * z, (x * x).sum(), (y * y).sum(), n * z * z,
              (x * y).sum(), z * x.sum(), z * y.sum()]
    dv = h ** 3
    S *= dv
    vol = S[0]
    c = S[1:4] / vol
    # second moments about the centroid
    xx = S[4] - vol * c[0] ** 2
    yy = S[5] - vol * c[1] ** 2
    zz = S[6] - vol * c[2] ** 2
    xy = S[7] - vol * c[0] * c[1]
    xz = S[8] - vol * c[0] * c[2]
    yz = S[9] - vol * c[1] * c[2]
    inertia = np.array([[yy + zz, -xy, -xz], [-xy, xx + zz, -yz], [-xz, -yz, xx + yy]])
    return vol, c, inertia


def template_mass_properties(template_csv):
    """Cached union mass properties of a template CSV (file next to it, .massprops)."""
    cache = template_csv + ".massprops"
    tc, tr = read_template_csv(template_csv)
    key = repr(np.concatenate([tc.ravel(), tr]).tolist())
    try:
        with open(cache) as f:
            lines = f.read().splitlines()
        if lines[0] == key:
            v = np.array(lines[1].split(), float)
            return v[0], v[1:4], v[4:13].reshape(3, 3)
    except (OSError, IndexError, ValueError):
        pass
    vol, c, inertia = union_mass_properties(tc, tr)
    with open(cache, "w") as f:
        f.write(key + "\n" + " ".join(FMT % x for x in [vol, *c, *inertia.ravel()]) + "\n")
    return vol, c, inertia


def write_rigid_infile(path, poses, template_csv, density):
    """fix rigid/small infile: the union's mass, centre and inertia for every body, so that
    LAMMPS integrates the same bodies as trackbed.  poses: list of (t, R), body i = mol i+1."""
    vol, c, inertia = template_mass_properties(template_csv)
    with open(path, "w") as f:
        f.write("# ID masstotal xcm ycm zcm ixx iyy izz ixy ixz iyz vxcm vycm vzcm lx ly lz "
                "ixcm iycm izcm\n")
        f.write("# union of the template spheres: volume %s m3, density %s\n" % (FMT % vol, density))
        f.write("%d\n" % len(poses))
        for i, (t, R) in enumerate(poses):
            x = t + R @ c
            I = density * (R @ inertia @ R.T)
            f.write("%d %s %s %s %s %s %s %s %s %s %s 0 0 0 0 0 0 0 0 0\n" % (
                i + 1, FMT % (density * vol), FMT % x[0], FMT % x[1], FMT % x[2],
                FMT % I[0, 0], FMT % I[1, 1], FMT % I[2, 2], FMT % I[0, 1], FMT % I[0, 2],
                FMT % I[1, 2]))


# --------------------------------------------------------------------------- rsa
def cmd_rsa(a):
    rng = np.random.default_rng(a.seed)
    d = sphere_diameters(a.n, a.dmin, a.dmax, rng)
    d = np.sort(d)[::-1]              # largest first: RSA reaches 0.40 polydisperse
    vol = np.sum(math.pi / 6 * d ** 3)
    h = vol / (a.phi * a.lx * a.ly)
    grid = CellGrid((0, 0, 0), (a.lx, a.ly, h), a.dmax)
    grid.reserve(a.n)
    tries_total = 0
    for i in range(a.n):
        r = d[i] / 2
        lo = np.array([r, r, r])
        hi = np.array([a.lx - r, a.ly - r, h - r])
        for t in range(a.maxtry):
            p = lo + rng.random(3) * (hi - lo)
            tries_total += 1
            if grid.fits([p], [r]):
                grid.add([p], [r])
                break
        else:
            sys.exit(f"rsa: sphere {i} (d={d[i]:.4f}) not placed after {a.maxtry} tries; "
                     f"lower --phi")
    # shuffle ids so that the size order does not correlate with the id order
    perm = rng.permutation(a.n)
    pos, dd = grid.P[perm], d[perm]
    box = [(-a.margin, a.lx + a.margin), (-a.margin, a.ly + a.margin), (-a.margin, h + a.margin)]
    write_lammps_data(a.out, pos, dd, a.density, box, title=f"RSA {a.n} spheres phi {a.phi}")
    print(f"rsa: {a.n} spheres, box {a.lx} x {a.ly} x {h:.4f} m, solid fraction {a.phi}, "
          f"mean tries {tries_total / a.n:.2f} -> {a.out}")


# --------------------------------------------------------------------------- template
def ellipsoid_surface(ax, n=200):
    u = np.linspace(0, 2 * math.pi, 2 * n, endpoint=False)
    v = np.linspace(0, math.pi, n)
    U, V = np.meshgrid(u, v)
    return np.stack([ax[0] * np.cos(U) * np.sin(V), ax[1] * np.sin(U) * np.sin(V),
                     ax[2] * np.cos(V)], axis=-1).reshape(-1, 3)


def cmd_template(a):
    rng = np.random.default_rng(a.seed)
    ax = np.array(a.axes)
    surf = ellipsoid_surface(ax)
    cen, rad = [], []
    while len(cen) < a.count:
        r = rng.uniform(a.rmin, a.rmax)
        c = (rng.random(3) * 2 - 1) * (ax - r)
        if np.sum((c / ax) ** 2) >= 1:
            continue
        # inside the ellipsoid with distance >= r to its surface (dense surface sampling,
        # with 0.2 mm of safety for the sampling resolution)
        if np.min(np.linalg.norm(surf - c, axis=1)) < r + 2e-4:
            continue
        # every new sphere must overlap an existing one: one connected clump
        if cen and not np.any(np.linalg.norm(np.array(cen) - c, axis=1) < np.array(rad) + r):
            continue
        cen.append(c)
        rad.append(r)
    cen, rad = np.array(cen), np.array(rad)
    with open(a.csv, "w") as f:
        f.write("x,y,z,radius\n")
        for c, r in zip(cen, rad):
            f.write("%s,%s,%s,%s\n" % (FMT % c[0], FMT % c[1], FMT % c[2], FMT % r))
    with open(a.mol, "w") as f:
        f.write(f"# trackbed bench clump template ({a.count} spheres, seed {a.seed})\n\n")
        f.write(f"{a.count} atoms\n\nCoords\n\n")
        for i, c in enumerate(cen):
            f.write("%d %s %s %s\n" % (i + 1, FMT % c[0], FMT % c[1], FMT % c[2]))
        f.write("\nTypes\n\n")
        for i in range(a.count):
            f.write(f"{i + 1} 1\n")
        f.write("\nDiameters\n\n")
        for i, r in enumerate(rad):
            f.write("%d %s\n" % (i + 1, FMT % (2 * r)))
        f.write("\nMasses\n\n")
        for i, r in enumerate(rad):
            f.write("%d %s\n" % (i + 1, FMT % (a.density * 4 / 3 * math.pi * r ** 3)))
    print(f"template: {a.count} spheres, radii {rad.min() * 1e3:.2f}-{rad.max() * 1e3:.2f} mm, "
          f"extent {np.ptp(cen - 0, axis=0) * 1e3} mm (centres) -> {a.csv}, {a.mol}")


def cmd_rsa_clumps(a):
    rng = np.random.default_rng(a.seed)
    tc, tr = read_template_csv(a.template)
    m = len(tr)
    bound = np.max(np.linalg.norm(tc, axis=1) + tr)      # bounding radius about the origin
    vol_b = 4 / 3 * math.pi * np.prod(a.axes)             # ellipsoid volume as body volume
    h = a.n * vol_b / (a.phi * a.lx * a.ly)
    grid = CellGrid((0, 0, 0), (a.lx, a.ly, h), 2 * tr.max())
    grid.reserve(a.n * m)
    mols, poses = [], []
    for b in range(a.n):
        for t in range(a.maxtry):
            R = quat_to_matrix(random_quaternion(rng))
            c = np.array([bound, bound, bound]) + rng.random(3) * (
                np.array([a.lx, a.ly, h]) - 2 * bound)
            pts = c + tc @ R.T
            if grid.fits(pts, tr):
                grid.add(pts, tr)
                poses.append((c, R))
                break
        else:
            sys.exit(f"rsa-clumps: body {b} not placed after {a.maxtry} tries; lower --phi")
        mols.extend([b + 1] * m)
    box = [(-a.margin, a.lx + a.margin), (-a.margin, a.ly + a.margin), (-a.margin, h + a.margin)]
    write_lammps_data(a.out, grid.P, 2 * np.tile(tr, a.n), a.density, box, mol=np.array(mols),
                      title=f"RSA {a.n} clumps")
    write_rigid_infile(a.out + ".rigid", poses, a.template, a.density)
    print(f"rsa-clumps: {a.n} bodies ({a.n * m} spheres), box {a.lx} x {a.ly} x {h:.4f} m -> {a.out}")


# --------------------------------------------------------------------------- conversions
def start_box(pos, rad, a):
    return [(-a.margin, a.lx + a.margin), (-a.margin, a.ly + a.margin),
            (-a.margin, float(np.max(pos[:, 2] + rad)) + a.top)]


def check_inside(pos, rad, a):
    lo = pos - rad[:, None]
    hi = pos + rad[:, None]
    # settled particles may touch the walls (small overlaps); anything far outside is an error
    tol = 0.5 * float(rad.max())
    if (lo[:, 0].min() < -tol or lo[:, 1].min() < -tol or lo[:, 2].min() < -tol
            or hi[:, 0].max() > a.lx + tol or hi[:, 1].max() > a.ly + tol):
        sys.exit("conversion: particles outside the walls: the settling failed")


def cmd_spheres(a):
    d = read_dump(a.dump)
    pos = np.stack([d["x"], d["y"], d["z"]], axis=1)
    rad = d["radius"]
    check_inside(pos, rad, a)
    write_lammps_data(a.data, pos, 2 * rad, a.density, start_box(pos, rad, a),
                      title=f"settled {len(rad)} spheres (zero velocity)")
    with open(a.csv, "w") as f:
        f.write("x,y,z,radius\n")
        for p, r in zip(pos, rad):
            f.write("%s,%s,%s,%s\n" % (FMT % p[0], FMT % p[1], FMT % p[2], FMT % r))
    phi = np.sum(4 / 3 * math.pi * rad ** 3) / (a.lx * a.ly * np.max(pos[:, 2] + rad))
    print(f"spheres: {len(rad)} settled spheres, bed top {np.max(pos[:, 2] + rad):.4f} m "
          f"(mean solid fraction below the top ~{phi:.3f}) -> {a.data}, {a.csv}")


def kabsch(P, Q):
    """R, t minimising |R P_i + t - Q_i| (P, Q: m x 3)."""
    pc, qc = P.mean(axis=0), Q.mean(axis=0)
    H = (P - pc).T @ (Q - qc)
    U, S, Vt = np.linalg.svd(H)
    dd = np.sign(np.linalg.det(Vt.T @ U.T))
    D = np.diag([1.0, 1.0, dd])
    R = Vt.T @ D @ U.T
    return R, qc - R @ pc


def cmd_clumps(a):
    d = read_dump(a.dump)
    tc, tr = read_template_csv(a.template)
    m = len(tr)
    mol = d["mol"].astype(int)
    pos = np.stack([d["x"], d["y"], d["z"]], axis=1)
    rad = d["radius"]
    check_inside(pos, rad, a)
    bodies = np.unique(mol)
    out_q, out_t, out_R, new_members = [], [], [], []
    worst = 0.0
    for b in bodies:
        idx = np.nonzero(mol == b)[0]            # sorted by atom id = template order
        if len(idx) != m:
            sys.exit(f"clumps: body {b} has {len(idx)} spheres, template has {m}")
        if np.max(np.abs(rad[idx] - tr)) > 1e-12:
            sys.exit(f"clumps: body {b}: member radii do not follow the template order")
        R, t = kabsch(tc, pos[idx])
        q = matrix_to_quat(R)
        R2 = quat_to_matrix(q)                   # what a reader of (t, q) rebuilds
        rebuilt = t + tc @ R2.T
        err = np.max(np.linalg.norm(rebuilt - pos[idx], axis=1))
        worst = max(worst, err)
        out_t.append(t)
        out_q.append(q)
        out_R.append(R2)
        new_members.append(rebuilt)
    if worst > a.tol:
        sys.exit(f"clumps: FAILED: max member position error of the fitted poses {worst:.3e} m "
                 f"> {a.tol:.1e} m")
    members = np.concatenate(new_members)
    newmol = np.repeat(np.arange(1, len(bodies) + 1), m)
    write_lammps_data(a.data, members, 2 * np.tile(tr, len(bodies)), a.density,
                      start_box(members, np.tile(tr, len(bodies)), a), mol=newmol,
                      title=f"settled {len(bodies)} clumps (zero velocity)")
    write_rigid_infile(a.data + ".rigid", list(zip(out_t, out_R)), a.template, a.density)
    with open(a.csv, "w") as f:
        f.write("x,y,z,template,qw,qx,qy,qz\n")
        for t, q in zip(out_t, out_q):
            f.write("%s,%s,%s,%s,%s,%s,%s,%s\n" % (FMT % t[0], FMT % t[1], FMT % t[2], a.name,
                                                   FMT % q[0], FMT % q[1], FMT % q[2], FMT % q[3]))
    print(f"clumps: {len(bodies)} bodies fitted onto template, max member position error "
          f"{worst:.2e} m -> {a.data}, {a.csv}")


def cmd_massprops(a):
    vol, c, inertia = template_mass_properties(a.template)
    tc, tr = read_template_csv(a.template)
    vsum = np.sum(4 / 3 * math.pi * tr ** 3)
    print(f"union volume {vol:.6e} m3 (sum of spheres {vsum:.6e}, ratio {vsum / vol:.3f}), "
          f"mass {a.density * vol:.6e} kg, centroid {c}, principal moments x density "
          f"{np.linalg.eigvalsh(inertia) * a.density}")


# --------------------------------------------------------------------------- log summary
def cmd_summary(a):
    txt = open(a.log).read()
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms",
                       txt)
    if not loops:
        sys.exit(f"summary: no Loop time in {a.log}")
    t, procs, steps, atoms = loops[a.run]
    chk = re.findall(r"^CHECK (.*)$", txt, re.M)
    print(f"loop_time_s={t} procs={procs} steps={steps} atoms={atoms} {chk[-1] if chk else ''}")


# --------------------------------------------------------------------------- settling in trackbed
def cmd_data_to_csv(a):
    """LAMMPS sphere data file (Atoms # sphere) -> trackbed particle CSV, rows in id order."""
    with open(a.data) as f:
        lines = f.read().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("Atoms")) + 2
    n = int(next(l.split()[0] for l in lines if l.endswith(" atoms")))
    rows = np.array([l.split()[:7] for l in lines[start:start + n]], dtype=float)
    rows = rows[np.argsort(rows[:, 0])]
    with open(a.csv, "w") as f:
        f.write("x,y,z,radius\n")
        for r in rows:
            f.write("%s,%s,%s,%s\n" % (FMT % r[4], FMT % r[5], FMT % r[6], FMT % (r[2] / 2)))
    print(f"data-to-csv: {n} spheres -> {a.csv}")


def read_vtu_points(path):
    """Points and point fields of a trackbed VTU (binary appended raw, UInt64 headers)."""
    with open(path, "rb") as f:
        raw = f.read()
    mark = raw.index(b'<AppendedData encoding="raw">')
    base = raw.index(b"_", mark) + 1
    header = raw[:mark].decode()
    kinds = {"Float64": np.float64, "Int64": np.int64, "UInt8": np.uint8}
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="(\d+)" '
                         r'format="appended" offset="(\d+)"/>', header):
        kind, name, comps, off = m.group(1), m.group(2), int(m.group(3)), int(m.group(4))
        nbytes = int(np.frombuffer(raw, np.uint64, 1, base + off)[0])
        arr = np.frombuffer(raw, kinds[kind], nbytes // np.dtype(kinds[kind]).itemsize,
                            base + off + 8)
        out[name] = arr.reshape(-1, comps) if comps > 1 else arr
    return out


def cmd_vtu_to_dump(a):
    """trackbed's last particles VTU -> the LAMMPS text dump the benchmark reads (ids = rows of
    the particle file + 1), so that a packing settled by trackbed feeds both codes."""
    v = read_vtu_points(a.vtu)
    pos, rad, ids = v["Points"], v["radius"], v["id"].astype(np.int64) + 1
    order = np.argsort(ids)
    with open(a.dump, "w") as f:
        f.write(f"ITEM: TIMESTEP\n{a.step}\nITEM: NUMBER OF ATOMS\n{len(ids)}\n")
        f.write("ITEM: BOX BOUNDS ff ff fm\n")
        top = float(np.max(pos[:, 2] + rad))
        for lo, hi in ((-a.margin, a.lx + a.margin), (-a.margin, a.ly + a.margin),
                       (-a.margin, top + a.margin)):
            f.write(f"{lo!r} {hi!r}\n")
        f.write("ITEM: ATOMS id type x y z radius\n")
        for i in order:
            f.write("%d 1 %s %s %s %s\n" % (ids[i], FMT % pos[i, 0], FMT % pos[i, 1],
                                              FMT % pos[i, 2], FMT % rad[i]))
    print(f"vtu-to-dump: {len(ids)} spheres -> {a.dump}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)

    def box_args(s):
        s.add_argument("--lx", type=float, required=True)
        s.add_argument("--ly", type=float, required=True)
        s.add_argument("--density", type=float, default=2800.0)
        s.add_argument("--margin", type=float, default=0.01,
                       help="box margin beyond the walls (m)")

    s = sub.add_parser("rsa")
    box_args(s)
    s.add_argument("--n", type=int, required=True)
    s.add_argument("--phi", type=float, default=0.40)
    s.add_argument("--dmin", type=float, default=0.022)
    s.add_argument("--dmax", type=float, default=0.063)
    s.add_argument("--seed", type=int, default=20240611)
    s.add_argument("--maxtry", type=int, default=1000000)
    s.add_argument("--out", required=True)
    s.set_defaults(f=cmd_rsa)

    s = sub.add_parser("template")
    s.add_argument("--count", type=int, default=12)
    s.add_argument("--rmin", type=float, default=0.0094)
    s.add_argument("--rmax", type=float, default=0.0125)
    s.add_argument("--axes", type=float, nargs=3, default=[0.030, 0.022, 0.016])
    s.add_argument("--density", type=float, default=2800.0)
    s.add_argument("--seed", type=int, default=12)
    s.add_argument("--csv", required=True)
    s.add_argument("--mol", required=True)
    s.set_defaults(f=cmd_template)

    s = sub.add_parser("rsa-clumps")
    box_args(s)
    s.add_argument("--n", type=int, required=True)
    s.add_argument("--phi", type=float, default=0.30,
                   help="solid fraction counting each body as its ellipsoid")
    s.add_argument("--axes", type=float, nargs=3, default=[0.030, 0.022, 0.016])
    s.add_argument("--template", required=True)
    s.add_argument("--seed", type=int, default=20240612)
    s.add_argument("--maxtry", type=int, default=1000000)
    s.add_argument("--out", required=True)
    s.set_defaults(f=cmd_rsa_clumps)

    for name, f in (("spheres", cmd_spheres), ("clumps", cmd_clumps)):
        s = sub.add_parser(name)
        box_args(s)
        s.add_argument("--dump", required=True)
        s.add_argument("--data", required=True)
        s.add_argument("--csv", required=True)
        s.add_argument("--top", type=float, default=0.10, help="box room above the bed (m)")
        if name == "clumps":
            s.add_argument("--template", required=True)
            s.add_argument("--name", default="bench12")
            s.add_argument("--tol", type=float, default=1e-9)
        s.set_defaults(f=f)

    s = sub.add_parser("data-to-csv")
    s.add_argument("--data", required=True)
    s.add_argument("--csv", required=True)
    s.set_defaults(f=cmd_data_to_csv)

    s = sub.add_parser("vtu-to-dump")
    s.add_argument("--vtu", required=True)
    s.add_argument("--dump", required=True)
    s.add_argument("--lx", type=float, required=True)
    s.add_argument("--ly", type=float, required=True)
    s.add_argument("--margin", type=float, default=0.01)
    s.add_argument("--step", type=int, default=0)
    s.set_defaults(f=cmd_vtu_to_dump)

    s = sub.add_parser("massprops")
    s.add_argument("--template", required=True)
    s.add_argument("--density", type=float, default=2800.0)
    s.set_defaults(f=cmd_massprops)

    s = sub.add_parser("summary")
    s.add_argument("--log", required=True)
    s.add_argument("--run", type=int, default=-1, help="which run of the log (default last)")
    s.set_defaults(f=cmd_summary)

    a = p.parse_args()
    a.f(a)


if __name__ == "__main__":
    main()
