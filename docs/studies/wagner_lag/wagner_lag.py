#!/usr/bin/env python3
"""Linearised 2D (and quasi-3D) Wagner planing strip: lag of wetted length and lift behind draft.

Needs numpy and scipy (pip install --user numpy scipy). Single process, < 1 min.
Writes results.csv next to this file. Every number in README.md comes from this script.

Model (derived in README.md):
  plate frame, fluid comes at speed U from +xi, trailing edge (TE) at xi = 0, spray root at xi = c(t).
  Linear, gravity-free, deep water. Odd extension of phi => unsteady thin-aerofoil problem with
  Kutta at TE, sqrt-singular leading edge at the moving spray root, wake convected at U.
  Wagner condition: free-surface elevation carried along the characteristics xi + U t = const
  meets the plate z_b = -h + alpha*xi at xi = c(t).
Units inside: length c0, time c0/U, elevations alpha*c0, vertical velocities U*alpha, rho = 1.
"""
import csv
import math
import os

import numpy as np
from scipy.optimize import brentq
from scipy.special import hankel2

HERE = os.path.dirname(os.path.abspath(__file__))

# ----------------------------------------------------------------------------- quadrature
NQ = 1400


def rot_grid(om, n=NQ, lo=1e-11):
    """Log grid on y in (0, inf) for integrals rotated onto s = -i y (weight exp(-om y))."""
    u = np.linspace(math.log(lo), math.log(60.0 / om + 200.0), n)
    y = np.exp(u)
    w = y * (u[1] - u[0])
    w[0] *= 0.5
    w[-1] *= 0.5
    return y, w


def rot_int(func, om, n=NQ):
    """int_0^inf func(s) exp(-i om s) ds, func analytic in the 4th quadrant, via s = -i y."""
    y, w = rot_grid(om, n)
    s = -1j * y
    return -1j * np.sum(w * func(s) * np.exp(-om * y))


def sig(s):
    """sqrt((1+s)/s) = sigma0 at xi = 1+s, and rho(x) = sqrt((x+1)/x) for wake distance x."""
    return np.sqrt(1 + s) / np.sqrt(s)


# ----------------------------------------------------------------------------- 2D kernels
def P_int(om):
    return rot_int(lambda s: sig(s) - 1.0, om)


def M_int(om):
    return rot_int(lambda s: 1.0 + (1.0 - 2.0 * s) * (sig(s) - 1.0), om)


def Kc_int(om):
    # 1/2 int s^-3/2 [ (1+s)^1/2 e^{-i om s} - (1+s)^-1/2 ] ds, both parts on the same rotated ray
    y, w = rot_grid(om)
    s = -1j * y
    f = 0.5 * s ** -1.5 * (np.sqrt(1 + s) * np.exp(-om * y) - 1 / np.sqrt(1 + s))
    return -1j * np.sum(w * f)


def W2_int(om, n=NQ):
    y, w = rot_grid(om, n)
    s = -1j * y
    f = w * sig(s) * np.exp(-om * y)
    Y = y[:, None] + y[None, :]
    return -(f[:, None] * f[None, :] / (1 - 1j * Y)).sum()


# ----------------------------------------------------------------------------- 3D correction
def dK(r, beta):
    """Horseshoe (span 2 beta) kernel minus 2D kernel 1/r, centre line, per Gamma/(2 pi)."""
    if beta is None:
        return 0.0 * r
    q = np.sqrt(r * r + beta * beta)
    return (beta / q - 1.0) / r - (1.0 - r / q) / beta


def dK0(beta):
    return -1.0 / beta  # limit r -> 0 (bound vortex on itself / wake at the plate)


def solve_case(om, beta):
    """Linear response to h1 = 1 (draft, units alpha c0) at frequency om (units U/c0).
    beta = half span / c0 (None = pure 2D). Returns dict."""
    P = P_int(om)
    Mi = M_int(om)
    Kc = Kc_int(om)
    W2 = W2_int(om)
    if beta is None:
        dKp, A1, E1, E2, D1, dK14 = 0, 0, 0, 0, 0, 0
    else:
        dKp = dK(np.array(-0.25), beta) * 1.0
        A1 = rot_int(lambda x: dK(0.5 + x, beta), om)
        E1 = rot_int(lambda s: dK(0.25 + s, beta), om)
        E2 = rot_int(lambda u: u * dK(1.0 + u, beta), om)
        dK14 = dK(np.array(0.25), beta) * 1.0
        D1 = -dK14 + 1j * om * E1
    Ve0 = 1.0 / (1.0 - 0.5 * dKp)
    G0 = math.pi * Ve0
    h1 = 1.0
    v1 = 1j * om * h1
    # unknowns x = [c1, Gam1, ve1]
    A = np.zeros((3, 3), complex)
    b = np.zeros(3, complex)
    # (1) ve1 - Gam1/(2pi) (dKp - i om A1) = v1
    A[0] = [0, -(dKp - 1j * om * A1) / (2 * math.pi), 1]
    b[0] = v1
    # (2) Gam1 (1 + i om P) - pi ve1 - pi Ve0 c1 = 0
    A[1] = [-math.pi * Ve0, 1 + 1j * om * P, -math.pi]
    # (3) Wagner: ve1 P + h1 + c1 (Ve0 Kc - 1 - G0/2pi (dK14 + 3/4 D1)) - i om Gam1 W2/2pi
    #             + Gam1/2pi (E1 - i om E2) = 0
    A[2] = [Ve0 * Kc - 1 - G0 / (2 * math.pi) * (dK14 + 0.75 * D1),
            (-1j * om * W2 + E1 - 1j * om * E2) / (2 * math.pi), P]
    b[2] = -h1
    c1, Gam1, ve1 = np.linalg.solve(A, b)
    M1 = 0.75 * math.pi * (ve1 + 2 * Ve0 * c1) - 0.5j * om * Gam1 * Mi
    L1 = 0.5 * (1j * om * M1 + Gam1)
    return dict(c1=c1, L1=L1, Gam1=Gam1, Ve0=Ve0, P=P, Kc=Kc, W2=W2)


def lag_from_c(om, c1):
    """first-order lag equivalent: c1/cg1 ~ A/(1 + i om tau); defined only for a phase lag
    between 0 and 90 deg (nan otherwise: no first-order lag reproduces it)"""
    ph = -np.angle(c1)
    if not (0.0 <= ph < 0.5 * math.pi):
        return float('nan')
    return math.tan(ph) / om


def lag_from_L(om, L1):
    """tau such that the simulator strip law L ~ V * c_e, c_e = c_g/(1+i om tau),
    has the same phase of lift vs draft as the Wagner model."""
    target = np.angle(L1)

    def f(tau):
        z = 1 / (1 + 1j * om * tau) + 1j * om
        return np.angle(z) - target
    # the simulator phase falls monotonically from tau = -0.99/om to its minimum, then rises
    # back towards 90 deg; use the falling branch. nan = lag beyond what the form can reach.
    taus = np.linspace(0.0, 20.0 / om, 20001)
    ph = np.angle(1 / (1 + 1j * om * taus) + 1j * om)
    tmin = taus[int(np.argmin(ph))]
    lo = -0.99 / om
    if f(lo) * f(tmin) > 0:
        return float('nan')
    return brentq(f, lo, tmin)


# ----------------------------------------------------------------------------- steady pile-up
def F2d(S):
    """2D steady: eta(c)/(alpha c) when the upstream integral is cut at xi = S c."""
    return math.acosh(math.sqrt(S)) + math.sqrt(S * (S - 1)) - (S - 1)


def G3d(beta):
    """quasi-3D steady pile-up eta(c)/(alpha c) with the horseshoe kernel (converges)."""
    u = np.linspace(math.log(1e-12), math.log(1e9), 20000)
    s = np.exp(u)
    w = s * (u[1] - u[0])
    dKp = dK(np.array(-0.25), beta) * 1.0
    Ve0 = 1.0 / (1.0 - 0.5 * dKp)
    f = Ve0 * (np.sqrt((1 + s) / s) - 1) + 0.5 * Ve0 * dK(0.25 + s, beta)
    return float(np.sum(w * f)), Ve0


# ----------------------------------------------------------------------------- stone states
RHO, G, M, R, CL = 1000.0, 9.81, 0.1, 0.05, 0.5


def seg_area(s):
    x = 1 - s / R
    return R * R * (math.acos(x) - x * math.sqrt(1 - x * x))


def chord(s):
    return 2 * math.sqrt(max(2 * R * s - s * s, 0.0))


def planing_state(U, alpha):
    """Appendix 2D disc model of whole_throw_memory.md: steady planing, C_L = 0.5."""
    need = M * G / (CL * RHO * U * U * math.sin(alpha) * math.cos(alpha))
    s = brentq(lambda s: seg_area(s) - need, 1e-9, 2 * R - 1e-9)
    k = CL * RHO * U * U * math.cos(alpha) * chord(s)      # dF_z/dd
    om = math.sqrt(k / M)
    return s, s * math.sin(alpha), om, chord(s)


def main():
    rows = []
    out = []
    # --- validation: lift with fixed chord reproduces half of Theodorsen's heave lift
    out.append("# check: fixed-chord heave lift vs 1/2 Theodorsen (k = om c/2U)")
    for om in (0.02, 0.2, 1.0):
        P = P_int(om)
        v1 = 1.0
        G1 = math.pi * v1 / (1 + 1j * om * P)
        M1 = 0.75 * math.pi * v1 - 0.5j * om * G1 * M_int(om)
        L1 = 0.5 * (1j * om * M1 + G1)
        k = om / 2
        CT = hankel2(1, k) / (hankel2(1, k) + 1j * hankel2(0, k))
        LT = math.pi / 8 * 1j * om + math.pi / 2 * CT
        out.append(f"om={om}: model {L1:.6f}  Theodorsen/2 {LT:.6f}")
        rows.append(dict(kind="check_theodorsen", om_hat=om, re=L1.real, im=L1.imag,
                         ref_re=LT.real, ref_im=LT.imag))
    # --- quadrature convergence on W2, Kc
    for om in (0.01, 0.2):
        a, bb = W2_int(om, 900), W2_int(om, 1400)
        out.append(f"W2({om}) n=900 {a:.6f} n=1400 {bb:.6f}; Kc {Kc_int(om):.6f}")
    # --- steady pile-up
    out.append("# steady 2D pile-up: h/(alpha c) = 1 - F(L/c), L = upstream cut-off")
    for S in (1.2, 1.47, 2, 10, 100, 1000):
        F = F2d(S)
        out.append(f"L/c={S}: F={F:.3f}  h/(alpha c)={1-F:.3f}")
        rows.append(dict(kind="steady2d", L_over_c=S, F=F, h_over_alpha_c=1 - F))
    out.append("# steady quasi-3D pile-up (horseshoe span b): G = eta(c)/(alpha c)")
    for bh in (2, 3, 5, 10, 13, 20, 50):
        Gv, Ve0 = G3d(bh / 2)
        out.append(f"b/c={bh}: G={Gv:.3f} Ve0={Ve0:.3f} h/(alpha c)={1-Gv:.3f}")
        rows.append(dict(kind="steady3d", b_over_c=bh, F=Gv, Ve0=Ve0, h_over_alpha_c=1 - Gv))
    # --- generic lag curves vs reduced frequency
    out.append("# generic: lambda_c (wetted length) and lambda_L (lift phase), units c0/U")
    out.append("# check: om -> 0 limit vs finite-difference static slope dc/dh of the 3D steady state")
    for bh in (2.0, 3.0, 5.0, 13.0):
        eta = lambda c: c * G3d(bh / 2 / c)[0]
        st = 1.0 / (1.0 - (eta(1.001) - eta(0.999)) / 0.002)
        c1 = solve_case(1e-3, bh / 2)["c1"]
        out.append(f"b/c={bh}: static dc/dh={st:.3f}  model(om=1e-3) c1={c1:.3f}")
        rows.append(dict(kind="check_static", b_over_c=bh, ref_re=st, re=c1.real, im=c1.imag))
    for bh in (None, 2.0, 3.0, 5.0, 13.0, 30.0):
        for om in (0.01, 0.02, 0.05, 0.1, 0.2, 0.5):
            r = solve_case(om, None if bh is None else bh / 2)
            lc = lag_from_c(om, r["c1"])
            lL = lag_from_L(om, r["L1"])
            out.append(f"b/c={bh} om={om}: c1/h1={r['c1']:.3f} |.|={abs(r['c1']):.3f} "
                       f"phase={np.degrees(np.angle(r['c1'])):7.1f} lam_c={lc:.3f} "
                       f"L1={r['L1']:.3f} phaseL={np.degrees(np.angle(r['L1'])):7.1f} lam_L={lL:.3f}")
            rows.append(dict(kind="generic", b_over_c=bh if bh else "inf", om_hat=om,
                             c_gain=abs(r["c1"]), c_phase_deg=float(np.degrees(np.angle(r["c1"]))),
                             lam_c=lc, L_re=r["L1"].real, L_im=r["L1"].imag,
                             L_phase_deg=float(np.degrees(np.angle(r["L1"]))), lam_L=lL))
    # --- stone cases
    out.append("# stone cases (R = 5 cm, 100 g, C_L = 0.5 planing state); c0 = geometric s")
    for adeg in (20.0, 10.0):
        a = math.radians(adeg)
        for U in (3.0, 5.0, 8.0, 12.0, 19.0):
            s, d, om, b = planing_state(U, a)
            omh = om * s / U
            for label, beta in (("2D", None), ("3D_b", b / s / 2), ("3D_pib4", math.pi / 8 * b / s)):
                r = solve_case(omh, beta)
                lc = lag_from_c(omh, r["c1"])
                lL = lag_from_L(omh, r["L1"])
                dmp = r["L1"].imag / (omh * r["L1"].real)
                # exit hysteresis of the harmonic loop: c on the way out minus way in at mean draft,
                # relative to the c amplitude: 2 sin(phase lag)
                hyst = 2 * math.sin(-np.angle(r["c1"]))
                row = dict(kind="stone", alpha_deg=adeg, U=U, s_mm=s * 1e3, d_mm=d * 1e3,
                           omega=om, om_hat=omh, b_mm=b * 1e3, b_over_c=b / s, model=label,
                           c_gain=abs(r["c1"]), c_phase_deg=float(np.degrees(np.angle(r["c1"]))),
                           L_re=r["L1"].real, L_im=r["L1"].imag,
                           L_phase_deg=float(np.degrees(np.angle(r["L1"]))),
                           lam_c=lc, lam_L=lL, damp_over_stiff=dmp,
                           tau_c_ms=lc * s / U * 1e3, tau_L_ms=lL * s / U * 1e3,
                           kappa_c=lc * s / R, kappa_L=lL * s / R, hyst=hyst,
                           falsifier_lag_ms=0.03 * R / U * 1e3)
                rows.append(row)
                out.append(f"a={adeg:4.0f} U={U:5.1f} s={s*1e3:6.2f}mm d={d*1e3:5.2f}mm om={om:6.1f} "
                           f"omh={omh:.4f} b/c={b/s:5.1f} {label:8s} |c1/h1|={abs(r['c1']):.3f} "
                           f"ph_c={np.degrees(np.angle(r['c1'])):7.1f} ph_L={np.degrees(np.angle(r['L1'])):7.1f} "
                           f"lam_c={lc:6.3f} lam_L={lL:6.3f} d/s={dmp:6.3f} "
                           f"kap_c={lc*s/R:6.3f} kap_L={lL*s/R:6.3f} tau_c={lc*s/U*1e3:.3f}ms "
                           f"tau_L={lL*s/U*1e3:.3f}ms hyst={hyst:.3f}")
    print("\n".join(out))
    keys = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(os.path.join(HERE, "results.csv"), "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=keys)
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


if __name__ == "__main__":
    main()
