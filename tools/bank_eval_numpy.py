#!/usr/bin/python3
"""Evaluate any material of an icobrdf bank at direction pairs with numpy + h5py alone.

    /usr/bin/python3 tools/bank_eval_numpy.py BANK.h5 MATERIAL PAIRS.csv

PAIRS.csv has the header theta_i,phi_i,theta_r,phi_r (degrees), as `icobrdf eval --at` reads it; the
values of f [1/sr] are printed one line per pair (channels comma-separated), as `icobrdf eval` prints them.

Every representation of docs/file-format.md is reconstructed here from its definition, independently of
icobrdf's C++ code:
  modes       f = sum_ab C_ab K_a(w_i) K_b(w_r)  (divided by cos(theta_i) when the spectrum is of g = f cos)
  half-angle  f = lobe(w_i, w_r)                 (the /materials/<name>/half_angle group)
  hybrid      f = max(0, modes + lobe)   (half-angle: max(0, lobe))
K_n^l = sqrt((n+1)/pi) R_n^|l|(rho) az_l(phi), rho = sqrt(2) sin(theta/2), az_l = cos(l phi) (l > 0),
1/sqrt(2) (l = 0), -sin(l phi) (l < 0); ANSI index j = (n(n+2)+l)/2.
"""
import math
import sys

import h5py
import numpy as np

HORIZON_SLACK = 1e-12  # z in [-slack, 0) is on the horizon, below it f = 0 (core/horizon conventions)


def _text(x):
    return x.decode() if isinstance(x, bytes) else str(x)


def zernike_radial(n, m, rho):
    """R_n^m(rho) by the explicit finite sum (exact in float64 for the orders banks use, n <= 30)."""
    out = np.zeros_like(rho)
    for s in range((n - m) // 2 + 1):
        c = (-1) ** s * math.factorial(n - s) / (
            math.factorial(s) * math.factorial((n + m) // 2 - s) * math.factorial((n - m) // 2 - s))
        out += c * rho ** (n - 2 * s)
    return out


def hemisphere_basis(order, w):
    """K_j(w) for j < (order+1)(order+2)/2, unit vectors w (pairs x 3): pairs x M."""
    z = np.clip(w[:, 2], 0.0, 1.0)
    rho = np.sqrt(np.clip(1.0 - z, 0.0, 1.0))  # rho^2 = 1 - cos(theta)
    phi = np.arctan2(w[:, 1], w[:, 0])
    cols = []
    for n in range(order + 1):
        for l in range(-n, n + 1, 2):
            r = zernike_radial(n, abs(l), rho)
            az = np.cos(l * phi) if l > 0 else (np.full_like(phi, 1 / math.sqrt(2)) if l == 0 else -np.sin(l * phi))
            cols.append(math.sqrt((n + 1) / math.pi) * r * az)
    return np.stack(cols, axis=1)


def half_angle(wi, wr):
    """(theta_h, phi_h, d): h = normalize(wi + wr), d = Ry(-theta_h) Rz(-phi_h) wi (Rusinkiewicz 1998).

    With R that rotation, R (wi + wr) = |wi + wr| z and R (wi - wr) is horizontal (|wi| = |wr|), so
    d = R wi = (|wi + wr| z + R (wi - wr)) / 2: computed so, d_xy is exactly 0 when wi = wr (phi_d = 0 there).
    """
    s, m = wi + wr, wi - wr
    norm = np.linalg.norm(s, axis=1)
    rho = np.hypot(s[:, 0], s[:, 1])
    theta_h = np.where(norm > 0, np.arctan2(rho, s[:, 2]), 0.0)
    phi_h = np.where(rho > 0, np.arctan2(s[:, 1], s[:, 0]), 0.0)
    c, sn = np.cos(phi_h), np.sin(phi_h)
    ct, st = np.cos(theta_h), np.sin(theta_h)
    x = c * m[:, 0] + sn * m[:, 1]
    y = -sn * m[:, 0] + c * m[:, 1]
    d = np.stack([0.5 * (ct * x - st * m[:, 2]), 0.5 * y, 0.5 * norm], axis=1)
    return theta_h, phi_h, d


def _linear(x, n, periodic):
    """Node indices (i0, i1) and weight of i1 for coordinates x in node units (0 .. n-1, or periodic in n)."""
    if periodic:
        x = np.mod(x, n)
        i0 = np.floor(x).astype(int) % n
        return i0, (i0 + 1) % n, x - np.floor(x)
    x = np.clip(x, 0.0, n - 1)
    i0 = np.minimum(np.floor(x).astype(int), n - 2)
    return i0, i0 + 1, x - i0


def _node(k, n, centred):
    """Node k of n in [0, 1]: k/(n-1), or (k+1/2)/n when the nodes are bin centres."""
    return (k + 0.5) / n if centred else k / (n - 1)


def _index(x, n, centred):
    """Position in node units of x in [0, 1] (the inverse of _node)."""
    return x * n - 0.5 if centred else x * (n - 1)


def _node_angles(n_t, n_ph, n_td, n_pd, warp, iso, stretch, centred):
    """True (theta, phi) of every h node and (theta_d, phi_d) of every d node (docs/file-format.md)."""
    k, j = np.divmod(np.arange(n_t * n_ph), n_ph)
    th = math.pi / 2 * _node(k, n_t, centred) ** warp
    ph = np.zeros_like(th) if iso else 2 * math.pi * j / n_ph
    if stretch is not None:
        axis, k1, k2 = stretch
        x1, x2 = k1 * np.sin(th) * np.cos(ph), k2 * np.sin(th) * np.sin(ph)
        hx, hy = math.cos(axis) * x1 - math.sin(axis) * x2, math.sin(axis) * x1 + math.cos(axis) * x2
        th = np.arctan2(np.hypot(hx, hy), np.cos(th))
        ph = np.where(np.hypot(hx, hy) > 0, np.arctan2(hy, hx), ph)
    a_, b_ = np.divmod(np.arange(n_td * n_pd), n_pd)
    return th, ph, math.pi / 2 * _node(a_, n_td, centred), math.pi * (b_ + (0.5 if centred else 0.0)) / n_pd


def _factor(g, name):
    """Factor values as stored: float64 / float32, or (format 4.0) integers times <name>_scale[set, r]."""
    x = g[name][...].astype(np.float64)
    if name + "_scale" in g:
        x = x * g[name + "_scale"][...][:, None, :]
    return x


def eval_lobe(g, channels, wi, wr):
    """The half-angle lobe of group g at pairs: pairs x channels."""
    a = {k: g.attrs[k] for k in g.attrs}
    n_t, n_ph, n_td, n_pd = (int(a[k]) for k in ("n_t", "n_phi_h", "n_theta_d", "n_phi_d"))
    warp, iso, quantity = float(a["h_warp"]), bool(a["isotropic"]), _text(a["quantity"])
    corners = _text(a["corners"]) if "corners" in a else "all"  # format 2.x lobes: every corner
    centred = "nodes" in a and _text(a["nodes"]) == "centres"
    stretch = (float(a["h_axis"]), float(a["h_scale_1"]), float(a["h_scale_2"])) if "h_axis" in a else None
    if stretch == (0.0, 1.0, 1.0):
        stretch = None
    u, v = _factor(g, "u"), _factor(g, "v")  # sets x h nodes x R, sets x d nodes x R
    if "factor_sets" in a and _text(a["factor_sets"]) == "shared":  # format 4.0: one set, channel scales
        s = g["channel_scales"][...]  # channels x R
        u = np.repeat(u, channels, axis=0)
        v = v[0][None, :, :] * s[:, None, :]
    theta_h, phi_h, d = half_angle(wi, wr)
    theta_g, phi_g = theta_h, phi_h  # the angles the h grid is laid out in
    if stretch is not None:
        axis, k1, k2 = stretch
        s = wi + wr  # a positive multiple of h: only the ratios matter
        x1 = (math.cos(axis) * s[:, 0] + math.sin(axis) * s[:, 1]) / k1
        x2 = (-math.sin(axis) * s[:, 0] + math.cos(axis) * s[:, 1]) / k2
        theta_g = np.arctan2(np.hypot(x1, x2), s[:, 2])
        phi_g = np.where(np.hypot(x1, x2) > 0, np.arctan2(x2, x1), 0.0)
    t = (theta_g / (math.pi / 2)) ** (1.0 / warp)
    t0, t1, wt = _linear(_index(t, n_t, centred), n_t, False)
    theta_d = np.arctan2(np.hypot(d[:, 0], d[:, 1]), d[:, 2])
    phi_d = np.arctan2(d[:, 1], d[:, 0])
    if not iso:
        phi_d = phi_d + phi_h  # anisotropic lobes: phi_d in the minimal-rotation frame (from the world's x axis)
    a0, a1, wa = _linear(_index(theta_d / (math.pi / 2), n_td, centred), n_td, False)
    b0, b1, wb = _linear(phi_d / math.pi * n_pd - (0.5 if centred else 0.0), n_pd, True)
    if iso:
        hw = [(t0, 1 - wt), (t1, wt)]
    else:
        j0, j1, wj = _linear(phi_g / (2 * math.pi) * n_ph, n_ph, True)
        hw = [(t0 * n_ph + j0, (1 - wt) * (1 - wj)), (t0 * n_ph + j1, (1 - wt) * wj),
              (t1 * n_ph + j0, wt * (1 - wj)), (t1 * n_ph + j1, wt * wj)]
    dw = [(a0 * n_pd + b0, (1 - wa) * (1 - wb)), (a0 * n_pd + b1, (1 - wa) * wb),
          (a1 * n_pd + b0, wa * (1 - wb)), (a1 * n_pd + b1, wa * wb)]
    # Corner node pairs below the horizon take no part when corners = "valid" (weights renormalized).
    nth, nph, ntd, npd = _node_angles(n_t, n_ph, n_td, n_pd, warp, iso, stretch, centred)
    out = np.zeros((wi.shape[0], channels))
    wsum = np.zeros(wi.shape[0])
    for hi, hwt in hw:
        for di, dwt in dw:
            w = hwt * dwt
            if corners == "valid":
                ok = (np.cos(nth[hi]) * np.cos(ntd[di]) -
                      np.sin(nth[hi]) * np.sin(ntd[di]) * np.abs(np.cos(npd[di] - nph[hi]))) >= -HORIZON_SLACK
                w = np.where(ok, w, 0.0)
            wsum += w
            for c in range(channels):
                out[:, c] += w * np.sum(u[c][hi] * v[c][di], axis=1)
    out /= np.where(wsum > 0, wsum, 1.0)[:, None]
    c0 = float(a["cosine_floor"])  # sin((pi/2) / (n_theta_d - 1))
    if quantity == "cosine":
        out /= (np.maximum(wi[:, 2], c0) * np.maximum(wr[:, 2], c0))[:, None]
    elif quantity == "mean-cosine":
        out /= np.maximum(0.5 * (wi[:, 2] + wr[:, 2]), c0)[:, None]
    return out


def eval_material(path, name, wi, wr):
    """f [1/sr] of material `name` at unit-vector pairs wi, wr (pairs x 3): pairs x channels."""
    with h5py.File(path, "r") as f:
        m = f["materials"][name]
        order = int(m.attrs["order"])
        cosine = bool(m.attrs["cosine"])
        C = m["C"][...]
        channels = C.shape[0]
        Ki, Kr = hemisphere_basis(order, wi), hemisphere_basis(order, wr)
        out = np.stack([np.einsum("pa,ab,pb->p", Ki, C[c], Kr) for c in range(channels)], axis=1)
        if cosine:
            out /= wi[:, 2:3]
        if "half_angle" in m:  # a material with a lobe is clamped at 0 (docs/file-format.md)
            out = np.maximum(out + eval_lobe(m["half_angle"], channels, wi, wr), 0.0)
    below = (wi[:, 2] < -HORIZON_SLACK) | (wr[:, 2] < -HORIZON_SLACK)
    out[below] = 0.0
    return out


def direction(theta_deg, phi_deg):
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=1)


def main(path, name, pairs_csv):
    a = np.loadtxt(pairs_csv, delimiter=",", skiprows=1, ndmin=2)
    values = eval_material(path, name, direction(a[:, 0], a[:, 1]), direction(a[:, 2], a[:, 3]))
    for row in values:
        print(",".join(f"{x:.17g}" for x in row))
    return values


if __name__ == "__main__":
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    main(*sys.argv[1:4])
