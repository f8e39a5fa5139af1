#!/usr/bin/python3
"""An independent simulator of the caterpillar (canonical geometry, ../shared/robots/
caterpillar.md) for the gap finder's foreign test cases: NOT the ODE model being diagnosed.

What differs from the ODE model (the caterpillar on the generic builder), on purpose:
  - resolution: every lump is split into two 15 mm sub-lumps joined by a silicone beam
    element (E 435 kPa, nu 0.33 over the lump's 40 x 25 mm section: axial EA/L, shear GA/L,
    bending EI/L, critically damped), so a lump is no longer rigid;
  - links: a bushing at the link's midpoint (axial and bending springs of the paper, a shear
    spring 20 times the axial one) instead of ODE's rigid shear row;
  - contact: penalty springs at the two bottom corners of every sub-lump with a sticking
    tangential spring capped by Coulomb friction (mu 3), instead of ODE's LCP contact with
    infinite friction; lump-lump contact is not modelled;
  - stroke stops: stiff penalty springs instead of speculative contact rows;
  - integration: semi-implicit Euler at 50 us instead of dWorldStep at 1 ms.

Effects are written in forms of their own (EFFECTS below), not the library's: a hose that
pulls the rear lump backwards and 30 degrees upwards, growing with distance; quadratic drag;
a first-order lag on the actuators' force; a tilted gravity; seal friction of the pistons
with a breakaway force above the sliding one (Stribeck form, smoothed through zero speed);
a softer silicone in the lumps (lump_modulus_pa: the inner beam elements' modulus); lossier
links between the lumps (link_damping_scale: their axial and bending damping times a factor).

Vectorised over a batch of runs that share one gait (numpy). Output: the recording CSV of
docs/recording-format.md (t, m1.x, m1.y, m1.z, ..., m6.z) from the end of the settle cycles.
"""
import numpy as np

# Canonical geometry and the paper's numbers.
LUMP_MASS, LUMP_X, LUMP_Z, LUMP_Y, SPACING = 0.030, 0.030, 0.025, 0.040, 0.032
FLEXURE = (1040.0, 0.12)   # links (1,2) (3,4) (5,6): N/m, N m/rad
SEGMENT = (446.0, 0.07)    # links (2,3) (4,5)
FORCE_N, RETURN_K, L_MIN, L_MAX = 8.8, 63.0, 0.051, 0.062
ATTACH_X, TOP_Z, BOTTOM_Z = 0.0095, 0.0125, -0.0080
E_SILICONE, NU = 435e3, 0.33
G = 9.81

SUB = 2                                   # sub-lumps per lump
N = 6 * SUB
M = LUMP_MASS / SUB
A = LUMP_X / SUB / 2                      # sub-lump half-length (m)
B = LUMP_Z / 2                            # half-height
I = M * ((2 * A) ** 2 + LUMP_Z ** 2) / 12

# Contact and stops.
K_CONTACT, ZETA_CONTACT, MU = 2.0e4, 0.5, 3.0
K_STICK = 2.0e4
K_STOP = 5.0e4
H = 5e-5


def _crit(k, m, zeta=1.0):
    return 2 * zeta * np.sqrt(k * m)


class Bushing:
    """Springs between body r's local point pr and body f's local point pf."""

    def __init__(self, r, f, pr, pf, k_ax, k_sh, kappa):
        self.r, self.f, self.pr, self.pf = r, f, np.array(pr), np.array(pf)
        self.k_ax, self.k_sh, self.kappa = k_ax, k_sh, kappa
        self.c_ax = _crit(k_ax, M / 2)
        self.c_sh = _crit(k_sh, M / 2)
        self.c_b = _crit(kappa, I / 2)


def _build():
    bushings = []
    # Inside a lump: a beam element of the lump's own silicone over the sub-lump spacing.
    area, length = LUMP_Y * LUMP_Z, 2 * A
    inertia = LUMP_Y * LUMP_Z ** 3 / 12
    for lump in range(6):
        for s in range(SUB - 1):
            r = lump * SUB + s
            bushings.append(Bushing(r, r + 1, (A, 0), (-A, 0), E_SILICONE * area / length,
                                    E_SILICONE / (2 * (1 + NU)) * area / length,
                                    E_SILICONE * inertia / length))
    # Between lumps: the paper's links at the midpoint.
    gap = SPACING / 2 - (LUMP_X / 2 - A)  # from the end sub-lump's centre to the midpoint
    for link in range(5):
        k_ax, kappa = FLEXURE if link % 2 == 0 else SEGMENT
        r = link * SUB + SUB - 1
        bushings.append(Bushing(r, r + 1, (gap, 0), (-gap, 0), k_ax, 20 * k_ax, kappa))
    # Actuators Tj, Bj between lumps 2j-1 and 2j (0-based lumps 2j, 2j+1): the attachment at
    # -9.5 mm of the rear lump, +9.5 mm of the front lump, in the sub-lump that holds it.
    acts = []
    for top in (True, False):
        for j in range(3):
            rear_lump, front_lump = 2 * j, 2 * j + 1
            z = TOP_Z if top else BOTTOM_Z
            rx = -ATTACH_X + LUMP_X / 2          # from the lump's rear face
            fx = ATTACH_X + LUMP_X / 2
            rs, fs = int(rx // (2 * A)), int(fx // (2 * A))
            acts.append((rear_lump * SUB + rs, (rx - (2 * rs + 1) * A, z),
                         front_lump * SUB + fs, (fx - (2 * fs + 1) * A, z)))
    return bushings, acts


BUSHINGS, ACTUATORS = _build()


class _Table:
    """Springs or actuators as arrays: body indices, local points, and one-hot matrices that
    scatter their forces onto the bodies (one matrix product instead of a Python loop)."""

    def __init__(self, r, pr, f, pf):
        self.r, self.f = np.array(r), np.array(f)
        self.prx, self.prz = np.array([p[0] for p in pr]), np.array([p[1] for p in pr])
        self.pfx, self.pfz = np.array([p[0] for p in pf]), np.array([p[1] for p in pf])
        self.sr = np.zeros((len(r), N))
        self.sf = np.zeros((len(f), N))
        self.sr[np.arange(len(r)), self.r] = 1
        self.sf[np.arange(len(f)), self.f] = 1


_BT = _Table([s.r for s in BUSHINGS], [s.pr for s in BUSHINGS], [s.f for s in BUSHINGS],
             [s.pf for s in BUSHINGS])
for _name in ("k_ax", "k_sh", "kappa", "c_ax", "c_sh", "c_b"):
    setattr(_BT, _name, np.array([getattr(s, _name) for s in BUSHINGS]))
# The beam elements inside lumps (the first 6 * (SUB - 1) bushings), which a run may soften.
_INNER = np.arange(len(BUSHINGS)) < 6 * (SUB - 1)
_AT = _Table([a[0] for a in ACTUATORS], [a[1] for a in ACTUATORS], [a[2] for a in ACTUATORS],
             [a[3] for a in ACTUATORS])


def _world(th, px, pz):
    c, s = np.cos(th), np.sin(th)
    return px * c + pz * s, -px * s + pz * c


class Rig:
    """A batch of runs of one gait (genes: 13 numbers), or of one gait per run (genes:
    one row of 13 per run); `effects` one dict per run (see EFFECTS)."""

    def __init__(self, genes, effects):
        self.genes = np.asarray(genes, dtype=float)
        self.period = self.genes[..., 12]
        self.b = len(effects)
        self.eff = effects
        lump_x = np.repeat(np.arange(6) * SPACING, SUB) + np.tile((2 * np.arange(SUB) + 1) * A - LUMP_X / 2, 6)
        self.x = np.tile(lump_x, (self.b, 1))
        # Rig variants per run (not effects): the contact's stiffness, damping ratio and
        # tangential (stick) stiffness.
        self.kc = np.array([e.get("contact_k", K_CONTACT) for e in effects])[:, None]
        self.zc = np.array([e.get("contact_zeta", ZETA_CONTACT) for e in effects])[:, None]
        self.ks = np.array([e.get("stick_k", K_STICK) for e in effects])[:, None]
        self.z = np.tile(B - M * G / 2 / self.kc, (1, N))
        self.th = np.zeros((self.b, N))
        self.vx = np.zeros((self.b, N))
        self.vz = np.zeros((self.b, N))
        self.w = np.zeros((self.b, N))
        self.anchor = np.full((self.b, N, 2), np.nan)   # stick points per bottom corner
        self.x0 = self.x.mean(axis=1)
        self.lag_force = np.zeros((self.b, 6))
        self.t = 0.0
        slope = np.array([e.get("slope_rad", 0.0) for e in effects])
        self.gx, self.gz = -G * np.sin(slope), -G * np.cos(slope)
        # The lumps' own silicone: its modulus per run (lump_modulus_pa) scales the inner beam
        # elements' springs, and their critical damping with the square root.
        scale = np.array([e.get("lump_modulus_pa", E_SILICONE) / E_SILICONE for e in effects])
        self.kscale = np.where(_INNER[None, :], scale[:, None], 1.0)
        self.cscale = np.sqrt(self.kscale)
        # Lossier links (link_damping_scale): the damping of the links between lumps, axial
        # and bending, times a factor; the lumps' own silicone and the shear rows keep theirs.
        loss = np.array([e.get("link_damping_scale", 1.0) for e in effects])
        self.dscale = np.where(_INNER[None, :], 1.0, loss[:, None])

    def on(self, t):
        """The ON mask: (6,) for one gait, (runs, 6) for a gait per run."""
        if self.genes.ndim == 2:
            period = self.period[:, None]
            phase = (t % period) / period
            a, d = self.genes[:, :6] % 1.0, self.genes[:, 6:12] % 1.0
            return np.where(a <= d, (phase >= a) & (phase < d), (phase >= a) | (phase < d))
        phase = (t % self.period) / self.period
        a, d = self.genes[:6] % 1.0, self.genes[6:12] % 1.0
        return np.where(a <= d, (phase >= a) & (phase < d), (phase >= a) | (phase < d))

    def _points(self, idx, px, pz):
        th = self.th[:, idx]
        ox, oz = _world(th, px, pz)
        w = self.w[:, idx]
        return (self.x[:, idx] + ox, self.z[:, idx] + oz, self.vx[:, idx] + w * oz,
                self.vz[:, idx] - w * ox, ox, oz)

    @staticmethod
    def _scatter(fx, fz, tq, T, gx, gz, fox, foz, rox, roz, torque):
        """Force (gx, gz) on each entry's front body at (fox, foz), its opposite on the rear
        body at (rox, roz), and a pure torque pair (+ on front, - on rear)."""
        fx += gx @ T.sf - gx @ T.sr
        fz += gz @ T.sf - gz @ T.sr
        tq += (foz * gx - fox * gz + torque) @ T.sf - (roz * gx - rox * gz + torque) @ T.sr

    def _apply(self, fx, fz, tq, i, ox, oz, gx, gz):
        fx[:, i] += gx
        fz[:, i] += gz
        tq[:, i] += oz * gx - ox * gz

    def step(self):
        b = self.b
        fx = np.zeros((b, N))
        fz = np.zeros((b, N))
        tq = np.zeros((b, N))
        fx += M * self.gx[:, None]
        fz += M * self.gz[:, None]
        T = _BT
        rx, rz, rvx, rvz, rox, roz = self._points(T.r, T.prx, T.prz)
        qx, qz, qvx, qvz, fox, foz = self._points(T.f, T.pfx, T.pfz)
        thm = 0.5 * (self.th[:, T.r] + self.th[:, T.f])
        ax, az = np.cos(thm), -np.sin(thm)        # body x axis in the x-z plane
        nx, nz = -az, ax                          # body z axis
        dx, dz, dvx, dvz = qx - rx, qz - rz, qvx - rvx, qvz - rvz
        ks, cs = self.kscale, self.cscale
        f_ax = -(ks * T.k_ax * (dx * ax + dz * az)
                 + cs * self.dscale * T.c_ax * (dvx * ax + dvz * az))
        f_sh = -(ks * T.k_sh * (dx * nx + dz * nz) + cs * T.c_sh * (dvx * nx + dvz * nz))
        gx, gz = f_ax * ax + f_sh * nx, f_ax * az + f_sh * nz
        bend = -(ks * T.kappa * (self.th[:, T.f] - self.th[:, T.r])
                 + cs * self.dscale * T.c_b * (self.w[:, T.f] - self.w[:, T.r]))
        self._scatter(fx, fz, tq, T, gx, gz, fox, foz, rox, roz, bend)
        on = self.on(self.t).astype(float)
        on = on if on.ndim == 2 else on[None, :]
        tau = np.array([e.get("actuator_lag_s", 0.0) for e in self.eff])
        target = FORCE_N * on * np.array([e.get("force_scale", 1.0) for e in self.eff])[:, None]
        alpha = np.where(tau > 0, 1 - np.exp(-H / np.maximum(tau, 1e-12)), 1.0)[:, None]
        self.lag_force += alpha * (target - self.lag_force)
        T = _AT
        rx, rz, rvx, rvz, rox, roz = self._points(T.r, T.prx, T.prz)
        qx, qz, qvx, qvz, fox, foz = self._points(T.f, T.pfx, T.pfz)
        dx, dz = qx - rx, qz - rz
        length = np.sqrt(dx * dx + dz * dz)
        ux, uz = dx / length, dz / length
        rate = (qvx - rvx) * ux + (qvz - rvz) * uz
        push = self.lag_force - RETURN_K * (length - L_MIN)
        push -= self._seal_friction(rate)
        c_stop = _crit(K_STOP, M / 2)
        push += np.where(length < L_MIN, K_STOP * (L_MIN - length) - c_stop * rate, 0.0)
        push += np.where(length > L_MAX, -K_STOP * (length - L_MAX) - c_stop * rate, 0.0)
        self._scatter(fx, fz, tq, T, push * ux, push * uz, fox, foz, rox, roz, 0.0)
        self._contacts(fx, fz, tq)
        self._effects(fx, fz, tq)
        self.vx += H * fx / M
        self.vz += H * fz / M
        self.w += H * tq / I
        self.x += H * self.vx
        self.z += H * self.vz
        self.th += H * self.w
        self.t += H

    def _seal_friction(self, rate):
        """Piston seal friction against the length's rate: sliding force Fc, breakaway Fs
        at low speed (Stribeck, speed scale 30 mm/s), through zero speed as tanh(v / 10 mm/s)
        (explicit: its slope at zero, Fs / 10 mm/s = 120 N s/m for 1.2 N, keeps h c / m
        below 1 on the 7.5 g reduced mass of two sub-lumps at 50 us)."""
        fc = np.array([e.get("seal_n", 0.0) for e in self.eff])[:, None]
        fs = np.array([e.get("seal_break_n", 0.0) for e in self.eff])[:, None]
        fs = np.maximum(fs, fc)
        level = fc + (fs - fc) * np.exp(-(rate / 0.03) ** 2)
        return level * np.tanh(rate / 0.01)

    def _contacts(self, fx, fz, tq):
        c_n = _crit(self.kc, M / 2, self.zc)
        c_t = _crit(self.ks, M / 2, self.zc)
        for corner, cx in enumerate((-A, A)):
            ox, oz = _world(self.th, cx, -B)
            px, pz = self.x + ox, self.z + oz
            vx, vz = self.vx + self.w * oz, self.vz - self.w * ox
            touching = pz < 0
            fn = np.where(touching, np.maximum(0.0, -self.kc * pz - c_n * vz), 0.0)
            anchor = self.anchor[:, :, corner]
            anchor = np.where(touching & np.isnan(anchor), px, anchor)
            anchor = np.where(touching, anchor, np.nan)
            ft = np.where(touching, -self.ks * (px - anchor) - c_t * vx, 0.0)
            limit = MU * fn
            slip = np.abs(ft) > limit
            ft = np.clip(ft, -limit, limit)
            # Sliding: move the stick point so that the spring holds the friction limit.
            anchor = np.where(slip, px + ft / self.ks, anchor)
            self.anchor[:, :, corner] = anchor
            fx += ft
            fz += fn
            tq += oz * ft - ox * fn

    def _effects(self, fx, fz, tq):
        travel = self.x.mean(axis=1) - self.x0
        hose = np.array([e.get("hose_n", 0.0) for e in self.eff])
        growth = np.array([e.get("hose_n_per_m", 0.0) for e in self.eff])
        pull = hose + growth * np.maximum(travel, 0.0)
        angle = np.radians(30.0)  # the hose leaves the robot backwards and upwards
        ox, oz = _world(self.th[:, 0], -A, B)  # the rear sub-lump's top rear corner
        self._apply(fx, fz, tq, 0, ox, oz, -pull * np.cos(angle), pull * np.sin(angle))
        drag = np.array([e.get("drag2_n_s2_per_m2", 0.0) for e in self.eff])[:, None]
        fx -= drag / (6 * SUB) * self.vx * np.abs(self.vx)

    def markers(self):
        """m_i at the top-face centre of lump i: the top point where its sub-lumps meet."""
        out = np.zeros((self.b, 6, 2))
        for lump in range(6):
            r, f = lump * SUB + SUB // 2 - 1, lump * SUB + SUB // 2
            ax, az = _world(self.th[:, r], A, B)
            bx, bz = _world(self.th[:, f], -A, B)
            out[:, lump, 0] = 0.5 * (self.x[:, r] + ax + self.x[:, f] + bx)
            out[:, lump, 1] = 0.5 * (self.z[:, r] + az + self.z[:, f] + bz)
        return out

    def diverged(self):
        return ~np.isfinite(self.x).all(axis=1) | (np.abs(self.vx) > 20).any(axis=1)


def simulate(genes, effects, settle=2, cycles=10, rate_hz=100):
    """Runs the batch; returns (t, markers[b, samples, 6, 2]) sampled from the end of the
    settle cycles (inclusive) at rate_hz."""
    rig = Rig(genes, effects)
    period = rig.period
    start, end = settle * period, (settle + cycles) * period
    dt_out = 1.0 / rate_hz
    n_out = int(np.floor((end - start) / dt_out + 1e-9)) + 1
    times = start + dt_out * np.arange(n_out)
    samples = np.zeros((rig.b, n_out, 6, 2))
    k = 0
    while k < n_out:
        while rig.t < times[k] - H / 2:
            rig.step()
        samples[:, k] = rig.markers()
        k += 1
    if rig.diverged().any():
        raise RuntimeError("rig2d: a run diverged")
    return times, samples


def travel(genes, effects, settle=1, cycles=5):
    """Forward travel per cycle (m) of the markers' mean x, run i with gait genes[i] and
    effects[i], over `cycles` periods after `settle`; NaN for a run that diverged."""
    rig = Rig(np.asarray(genes, dtype=float), effects)
    start, end = settle * rig.period, (settle + cycles) * rig.period
    x0 = np.full(rig.b, np.nan)
    x1 = np.full(rig.b, np.nan)
    while True:
        x = rig.markers()[:, :, 0].mean(axis=1)
        take0 = np.isnan(x0) & (rig.t >= start - H / 2)
        x0[take0] = x[take0]
        take1 = np.isnan(x1) & (rig.t >= end - H / 2)
        x1[take1] = x[take1]
        if not np.isnan(x1).any():
            break
        rig.step()
    out = (x1 - x0) / cycles
    out[rig.diverged()] = np.nan
    return out


def write_csv(path, times, markers):
    """One run's markers as a recording CSV (y = 0: the rig is planar)."""
    cols = ["t"] + [f"m{i}.{a}" for i in range(1, 7) for a in ("x", "y", "z")]
    with open(path, "w") as f:
        f.write(",".join(cols) + "\n")
        for t, m in zip(times, markers):
            cells = [f"{t:.6f}"]
            for i in range(6):
                cells += [f"{m[i, 0]:.9g}", "0", f"{m[i, 1]:.9g}"]
            f.write(",".join(cells) + "\n")
