"""The DEM's compiled loops (numba, ``cache=True``): vertex positions, the Verlet candidate list
with its stiffnesses, crushing caps and coincident-corner twins, and the central-difference time
loop.

Conventions (``model``): blocks are rigid polygons, vertex k of block owner[k] sits at
pos + R(θ) rel[k]; edge k runs from vertex k to vertex nxt[k] (counter-clockwise, outward
normal (d_z, −d_x)/|d|). A candidate c pairs a vertex cv[c] of block i with an edge ce[c] of
block j; its normal n is the edge's outward normal, its tangent t the edge's direction.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["world_vertices", "build_candidates", "advance", "FLAT_CONE"]

#: the normal cone's half-angle [rad] of a flat vertex (a point inserted on a straight edge,
#: ``model``'s joint_segments): it touches an edge whose inward normal lies within this of its
#: own outward normal. A corner's cone is its two edges' normals; a flat vertex has one normal,
#: so the corners' small tolerance would drop it once the two blocks turn by 0.05 rad apart,
#: while it still lies in the other's face (a rocking block's crushed toe)
FLAT_CONE = math.pi / 4
SIN_FLAT_CONE = math.sin(FLAT_CONE)


@njit(cache=True)
def world_vertices(pos, th, rel, owner, X):
    n = pos.shape[0]
    c = np.empty(n)
    s = np.empty(n)
    for b in range(n):
        c[b] = math.cos(th[b])
        s[b] = math.sin(th[b])
    for k in range(rel.shape[0]):
        b = owner[k]
        X[k, 0] = pos[b, 0] + c[b] * rel[k, 0] - s[b] * rel[k, 1]
        X[k, 1] = pos[b, 1] + s[b] * rel[k, 0] + c[b] * rel[k, 1]


@njit(cache=True)
def _edge(X, nxt, e):
    """(A_x, A_z, t_x, t_z, L) of edge e."""
    ax, az = X[e, 0], X[e, 1]
    dx, dz = X[nxt[e], 0] - ax, X[nxt[e], 1] - az
    L = math.sqrt(dx * dx + dz * dz)
    return ax, az, dx / L, dz / L, L


@njit(cache=True)
def _in_cone(X, nxt, prv, flat, p, mx, mz, sin_tol):
    """Does the unit direction (mx, mz) lie in the outward normal cone of vertex p (between
    the normals of its two edges, counter-clockwise), widened by sin_tol = sin(tol)? A flat
    vertex (flat[p]: its two edges collinear, one normal): within FLAT_CONE (> any tol
    allowed) of its normal, on its side (``_cone_test``)."""
    a = prv[p]
    d1x, d1z = X[p, 0] - X[a, 0], X[p, 1] - X[a, 1]
    l1 = math.sqrt(d1x * d1x + d1z * d1z)
    b = nxt[p]
    d2x, d2z = X[b, 0] - X[p, 0], X[b, 1] - X[p, 1]
    l2 = math.sqrt(d2x * d2x + d2z * d2z)
    return _cone_test(d1z / l1, -d1x / l1, d2z / l2, -d2x / l2, flat[p], mx, mz, sin_tol)


@njit(cache=True)
def _cone_test(n1x, n1z, n2x, n2z, fl, mx, mz, sin_tol):
    """``_in_cone`` given the outward normals of the vertex's edge in (n1) and edge out
    (n2)."""
    st = SIN_FLAT_CONE if fl else sin_tol
    return ((n1x * mz - n1z * mx >= -st) and (mx * n2z - mz * n2x >= -st)
            and (not fl or mx * n1x + mz * n1z > 0.0))


@njit(cache=True)
def edge_table(X, nxt, T):
    """T[e] = (t_x, t_z, L) of every edge e (from vertex e to nxt[e]): ``_edge`` once each."""
    for e in range(X.shape[0]):
        _, _, tx, tz, L = _edge(X, nxt, e)
        T[e, 0] = tx
        T[e, 1] = tz
        T[e, 2] = L


@njit(cache=True)
def _find(keys, m, key):
    """Index of key in the sorted keys[:m], or -1."""
    lo, hi = 0, m
    while lo < hi:
        mid = (lo + hi) // 2
        if keys[mid] < key:
            lo = mid + 1
        else:
            hi = mid
    if lo < m and keys[lo] == key:
        return lo
    return -1


@njit(cache=True)
def _grow(a, cap):
    b = np.empty(cap, a.dtype)
    b[:a.shape[0]] = a
    return b


@njit(cache=True)
def build_candidates(X, offsets, nxt, prv, flat, owner, fixed, margin, coinc, cone_build,
                     old_key, old_kn, old_ks, old_fs, old_tied, old_sl, old_cap, old_dp, n_old,
                     kn, ks_ratio, thick, fac_x, fac_f, xref, trib_floor, tie_base,
                     fc, dep_f, dep_w, x_j):
    """The Verlet list: every (vertex of i, edge of j) pair of distinct blocks, not both fixed,
    with the vertex within ``margin`` of the edge's line and span and its normal cone within
    ``cone_build`` of the edge's inward normal. A pair already listed (same key
    vertex·P + edge) keeps its stiffnesses, shear force, tie, cap and plastic closure, and
    stays listed while it penetrates by less than margin + its plastic closure (a crushed
    contact keeps its memory); a new one gets kn·trib·thick·factor, trib = half the overlap of
    the vertex's adjacent edge (the one facing the edge) with the edge (a flat vertex: half
    the overlap of each of its two edges), at least trib_floor × the shorter of the two,
    factor fac_f if the tributary's centre has x < fac_x. That x is the centre's material
    point on its edge in the reference configuration (``xref``: every vertex's x before any
    motion), and "<" holds by more than ``coinc``: an interface edge at x = fac_x (the
    façade's inner face) keeps factor 1 however the blocks have moved. Its crushing cap is
    fc·trib·depth, depth dep_f if the tributary's centre has x < x_j, else dep_w (infinite
    for fc = 0). ``tie_base``: new contacts with a fixed block that touch (gap < coinc) are
    tied. Twins: a pair whose vertex lies within margin of an end of its edge, and the
    reverse pair at that corner (coincident corners, drifted apart by at most margin); only
    one of them acts at a time (``advance``). Returns sorted arrays (key, v, e, kn, ks, fs,
    tied, slip, twin, cap, plastic closure)."""
    n = offsets.shape[0] - 1
    P = X.shape[0]
    sin_build = math.sin(cone_build)
    lo = np.empty((n, 2))
    hi = np.empty((n, 2))
    for b in range(n):
        lo[b, 0] = 1e300
        lo[b, 1] = 1e300
        hi[b, 0] = -1e300
        hi[b, 1] = -1e300
        for k in range(offsets[b], offsets[b + 1]):
            lo[b, 0] = min(lo[b, 0], X[k, 0])
            lo[b, 1] = min(lo[b, 1], X[k, 1])
            hi[b, 0] = max(hi[b, 0], X[k, 0])
            hi[b, 1] = max(hi[b, 1], X[k, 1])
    order = np.argsort(lo[:, 0])
    dp_max = 0.0
    for o in range(n_old):
        dp_max = max(dp_max, old_dp[o])
    cap = 1024
    key = np.empty(cap, np.int64)
    kn_c = np.empty(cap)
    ks_c = np.empty(cap)
    fs_c = np.empty(cap)
    tied = np.empty(cap, np.bool_)
    sl_c = np.empty(cap)
    cn_c = np.empty(cap)
    dp_c = np.empty(cap)
    m = 0
    for oi in range(n):
        i = order[oi]
        for oj in range(oi + 1, n):
            j = order[oj]
            if lo[j, 0] > hi[i, 0] + margin:
                break
            if fixed[i] and fixed[j]:
                continue
            if lo[j, 1] > hi[i, 1] + margin or lo[i, 1] > hi[j, 1] + margin:
                continue
            for side in range(2):
                bi = i if side == 0 else j
                bj = j if side == 0 else i
                for p in range(offsets[bi], offsets[bi + 1]):
                    for e in range(offsets[bj], offsets[bj + 1]):
                        ax, az, tx, tz, L = _edge(X, nxt, e)
                        nx, nz = tz, -tx
                        rx, rz = X[p, 0] - ax, X[p, 1] - az
                        s = rx * tx + rz * tz
                        g = rx * nx + rz * nz
                        if g > margin or g < -margin - dp_max or s < -margin \
                                or s > L + margin:
                            continue
                        kk = p * P + e
                        if g < -margin:           # deeper: only a crushed pair stays
                            o = _find(old_key, n_old, kk)
                            if o < 0 or g < -margin - old_dp[o]:
                                continue
                        if not _in_cone(X, nxt, prv, flat, p, -nx, -nz, sin_build):
                            continue
                        if m == cap:
                            cap *= 2
                            key = _grow(key, cap)
                            kn_c = _grow(kn_c, cap)
                            ks_c = _grow(ks_c, cap)
                            fs_c = _grow(fs_c, cap)
                            tied = _grow(tied, cap)
                            sl_c = _grow(sl_c, cap)
                            cn_c = _grow(cn_c, cap)
                            dp_c = _grow(dp_c, cap)
                        key[m] = kk
                        o = _find(old_key, n_old, kk)
                        if o >= 0:
                            kn_c[m] = old_kn[o]
                            ks_c[m] = old_ks[o]
                            fs_c[m] = old_fs[o]
                            tied[m] = old_tied[o]
                            sl_c[m] = old_sl[o]
                            cn_c[m] = old_cap[o]
                            dp_c[m] = old_dp[o]
                            m += 1
                            continue
                        # tributary: the adjacent edge of p whose normal faces the edge
                        q1 = prv[p]
                        q2 = nxt[p]
                        d1x, d1z = X[p, 0] - X[q1, 0], X[p, 1] - X[q1, 1]
                        d2x, d2z = X[q2, 0] - X[p, 0], X[q2, 1] - X[p, 1]
                        l1 = math.sqrt(d1x * d1x + d1z * d1z)
                        l2 = math.sqrt(d2x * d2x + d2z * d2z)
                        c1 = (d1z * nx - d1x * nz) / l1   # n1 · n
                        c2 = (d2z * nx - d2x * nz) / l2
                        q = q1 if c1 < c2 else q2
                        ladj = l1 if c1 < c2 else l2
                        sq = (X[q, 0] - ax) * tx + (X[q, 1] - az) * tz
                        sp = min(max(s, 0.0), L)
                        sq = min(max(sq, 0.0), L)
                        if flat[p]:
                            # a flat vertex: half of each edge's overlap, one on either side
                            s1 = (X[q1, 0] - ax) * tx + (X[q1, 1] - az) * tz
                            s2 = (X[q2, 0] - ax) * tx + (X[q2, 1] - az) * tz
                            s1 = min(max(s1, 0.0), L)
                            s2 = min(max(s2, 0.0), L)
                            trib = 0.5 * (abs(s1 - sp) + abs(s2 - sp))
                            ladj = min(l1, l2)
                            sc = sp + 0.25 * ((s1 - sp) + (s2 - sp))
                            if trib < trib_floor * min(L, ladj):
                                trib = trib_floor * min(L, ladj)
                        else:
                            trib = 0.5 * abs(sq - sp)
                            trib = max(trib, trib_floor * min(L, ladj))
                            sc = sp + (0.5 * trib if sq >= sp else -0.5 * trib)
                        xc = xref[e] + (xref[nxt[e]] - xref[e]) * (sc / L)
                        f = fac_f if xc < fac_x - coinc else 1.0
                        kn_c[m] = kn * trib * thick * f
                        if fc > 0.0:
                            cn_c[m] = fc * trib * (dep_f if xc < x_j - coinc else dep_w)
                        else:
                            cn_c[m] = np.inf
                        dp_c[m] = 0.0
                        ks_c[m] = ks_ratio * kn_c[m]
                        fs_c[m] = 0.0
                        tied[m] = tie_base and (fixed[bi] or fixed[bj]) and g < coinc
                        sl_c[m] = 0.0
                        m += 1
    srt = np.argsort(key[:m])
    key = key[srt].copy()
    kn_c = kn_c[srt].copy()
    ks_c = ks_c[srt].copy()
    fs_c = fs_c[srt].copy()
    tied = tied[srt].copy()
    sl_c = sl_c[srt].copy()
    cn_c = cn_c[srt].copy()
    dp_c = dp_c[srt].copy()
    cv = key // P
    ce = key % P
    # twins at coincident corners: (p on e of j) with p within ``margin`` of an end q of e,
    # and (q on the edge of p's block adjacent to p whose normal is opposite e's). Corners
    # slid apart along the joint leave only one of the two inside its edge's span, so the
    # wide tolerance never suppresses a distinct contact point
    twin = np.full(m, -1, np.int64)
    for c in range(m):
        p = cv[c]
        e = ce[c]
        for end in range(2):
            q = e if end == 0 else nxt[e]
            dx, dz = X[p, 0] - X[q, 0], X[p, 1] - X[q, 1]
            if dx * dx + dz * dz > margin * margin:
                continue
            for ep in (p, prv[p]):
                o = _find(key, m, q * P + ep)
                if o < 0:
                    continue
                _, _, tx1, tz1, _ = _edge(X, nxt, e)
                _, _, tx2, tz2, _ = _edge(X, nxt, ep)
                if tx1 * tx2 + tz1 * tz2 < -0.99:
                    twin[c] = o
    return key, cv, ce, kn_c, ks_c, fs_c, tied, sl_c, twin, cn_c, dp_c


@njit(cache=True, nogil=True)
def advance(nsteps, dt, pos, th, vel, om, rel, offsets, nxt, prv, flat, owner, fixed, inv_m,
            inv_I, mass, radius, g, fric, ag, ag_t0, damping,
            key, cv, ce, kn_c, ks_c, fs_c, tied, sl_c, twin, cn_c, dp_c,
            build_pos, build_th, margin, coinc, cone_build, cone_tol, edge_tol,
            kn, ks_ratio, thick, fac_x, fac_f, xref, trib_floor, fc, dep_f, dep_w, x_j,
            watch, ref_pos, ref_th, disp_limit, rot_limit, check_every,
            slip_base, slip_bed, work, rec_every, rec, z_ref, vel_tol, loads, ties, tstate):
    """Central differences for nsteps steps of dt. Releases the GIL (``model`` runs it through
    ``_threads.call``, so that a signal interrupts the wait for it).

    A real wall (``model``; docs/real-walls.md): ``loads`` (n_l, 5) rows (block, r_x, r_z,
    F_x, F_z): a dead force (F_x, F_z) at the point r of the block's frame (from its
    centroid, turning with it), the floors' loads. ``ties`` (n_t, 8) rows (block, r_x, r_z,
    x0, k, T_y, δ_u, bilateral): a horizontal spring from the point r of the block to a fixed
    anchor, elongation δ = x0 − x(r) (outwards positive), force k (δ − δ_p) towards +x,
    capped at T_y (δ_p the plastic elongation, ``tstate[:, 0]``), slack below zero unless
    ``bilateral`` (a restraint, capped at ±T_y), broken for good past δ_u (``tstate[:, 1]``).

    Forces at x_n: gravity −m g ẑ, the ground's inertia −m a_g(t) x̂ (ag[k] at t = ag_t0 + k
    dt, zero past the array), the contacts; with ``damping`` > 0 Cundall's local damping.
    v_{n+1/2} = v_{n−1/2} + dt F/m, x_{n+1} = x_n + dt v_{n+1/2}. Contacts: gap g = (P − A)·n,
    active when g < −δ_p (δ_p the contact's plastic closure, dp_c; 0 until it crushes), the
    vertex within the edge's span (± edge_tol) and the edge's inward normal in the vertex's
    cone (± cone_tol), or when tied. Normal force kn·(−g − δ_p), elastic–perfectly plastic:
    capped at the contact's cap cn_c (f_c × tributary × depth, ``build_candidates``), the
    excess closure added to δ_p, which stays (the crushed material is gone); no tension
    unless tied; shear force incremented by −ks·(relative tangential velocity)·dt and capped
    at fric·Fn (the excess over ks is the plastic slip, summed per contact in sl_c; per
    block, slip_base and slip_bed keep the largest of its contacts' slips with a fixed block
    and in bed joints; ``work`` (6,) sums, in J, the friction work (each step's plastic slip
    times the mean of the shear force at the step's start and the cap, as PFC's slip energy)
    with fixed blocks, in bed joints (|n_z| > 0.9) at x < fac_x (the façade strip) and
    beyond, and in the other joints, the crushing work (cap × plastic closure), and the
    ground's inertia's work on the blocks, Σ −m a_g u dt.
    Of two twins only the one whose
    vertex belongs to the lower block index acts while both are valid; the other carries its
    shear force and plastic closure. The list is rebuilt (``build_candidates``) once a block
    has moved by margin/2. Every check_every steps: stop (status 1) if a watched block has
    moved outwards (−x) by more than disp_limit or turned by more than rot_limit; with damping, stop
    (status 2) once every free block is slower than vel_tol. rec (rows, 8) gets, every
    rec_every steps, t, kinetic, potential (m g (z − z_ref)), elastic energy, the
    x-displacement and rotation of the first watched block, then work[:5].sum() and
    work[5] so far.
    Returns (steps done, status, rows recorded, key, cv, ce, kn_c, ks_c, fs_c, tied, sl_c, twin,
    cn_c, dp_c, n_builds)."""
    n = pos.shape[0]
    P = rel.shape[0]
    X = np.empty((P, 2))
    F = np.empty((n, 3))
    crush = fc > 0.0          # f_c infinite: the caps and closures are never read
    nrow = 0
    builds = 0
    status = 0
    w0 = -1
    for b in range(n):
        if watch[b]:
            w0 = b
            break
    step = 0
    m = key.shape[0]
    acted = np.zeros(m, np.bool_)
    geo = np.empty((m, 3))      # per acting contact: its edge's unit tangent and the gap
    T = np.empty((X.shape[0], 3))     # per edge, each step: unit tangent and length
    sin_tol = math.sin(cone_tol)
    for step in range(nsteps):
        # rebuild the Verlet list once a block has moved by margin/2
        moved = 0.0
        for b in range(n):
            if fixed[b]:
                continue
            dx = pos[b, 0] - build_pos[b, 0]
            dz = pos[b, 1] - build_pos[b, 1]
            d = math.sqrt(dx * dx + dz * dz) + abs(th[b] - build_th[b]) * radius[b]
            if d > moved:
                moved = d
        world_vertices(pos, th, rel, owner, X)
        edge_table(X, nxt, T)
        if moved > 0.5 * margin:
            key, cv, ce, kn_c, ks_c, fs_c, tied, sl_c, twin, cn_c, dp_c = build_candidates(
                X, offsets, nxt, prv, flat, owner, fixed, margin, coinc, cone_build,
                key, kn_c, ks_c, fs_c, tied, sl_c, cn_c, dp_c, key.shape[0],
                kn, ks_ratio, thick, fac_x, fac_f, xref, trib_floor, False, fc, dep_f, dep_w,
                x_j)
            m = key.shape[0]
            acted = np.zeros(m, np.bool_)
            builds += 1
            for b in range(n):
                build_pos[b, 0] = pos[b, 0]
                build_pos[b, 1] = pos[b, 1]
                build_th[b] = th[b]
        k = step
        a_g = ag[k] if k < ag.shape[0] else 0.0
        for b in range(n):
            F[b, 0] = -mass[b] * a_g
            F[b, 1] = -mass[b] * g
            F[b, 2] = 0.0
        record = rec_every > 0 and step % rec_every == 0 and nrow < rec.shape[0]
        elastic = 0.0
        for q in range(loads.shape[0]):
            b = int(loads[q, 0])
            cq, sq = math.cos(th[b]), math.sin(th[b])
            rx = cq * loads[q, 1] - sq * loads[q, 2]
            rz = sq * loads[q, 1] + cq * loads[q, 2]
            F[b, 0] += loads[q, 3]
            F[b, 1] += loads[q, 4]
            F[b, 2] += rx * loads[q, 4] - rz * loads[q, 3]
        for q in range(ties.shape[0]):
            if tstate[q, 1] > 0.0:
                continue                              # broken
            b = int(ties[q, 0])
            cq, sq = math.cos(th[b]), math.sin(th[b])
            rx = cq * ties[q, 1] - sq * ties[q, 2]
            rz = sq * ties[q, 1] + cq * ties[q, 2]
            delta = ties[q, 3] - (pos[b, 0] + rx)
            if delta > ties[q, 6]:
                tstate[q, 1] = 1.0
                continue
            kt, ty = ties[q, 4], ties[q, 5]
            ft = kt * (delta - tstate[q, 0])
            if ft > ty:
                tstate[q, 0] = delta - ty / kt
                ft = ty
            elif ties[q, 7] > 0.0 and ft < -ty:
                tstate[q, 0] = delta + ty / kt
                ft = -ty
            elif ties[q, 7] == 0.0 and ft < 0.0:
                ft = 0.0                              # slack
            if record:
                elastic += 0.5 * ft * ft / kt
            F[b, 0] += ft
            F[b, 2] -= rz * ft
        if geo.shape[0] < m:
            geo = np.empty((m, 3))
        for c in range(m):
            acted[c] = False
            p = cv[c]
            e = ce[c]
            tx, tz, L = T[e, 0], T[e, 1], T[e, 2]
            nx, nz = tz, -tx
            rx, rz = X[p, 0] - X[e, 0], X[p, 1] - X[e, 1]
            s = rx * tx + rz * tz
            gap = rx * nx + rz * nz
            if not tied[c]:
                if gap >= (-dp_c[c] if crush else 0.0) or s < -edge_tol or s > L + edge_tol:
                    fs_c[c] = 0.0
                    continue
                a = prv[p]
                if not _cone_test(T[a, 1], -T[a, 0], T[p, 1], -T[p, 0], flat[p], -nx, -nz,
                                  sin_tol):
                    fs_c[c] = 0.0
                    continue
            acted[c] = True
            geo[c, 0], geo[c, 1], geo[c, 2] = tx, tz, gap     # for the forces below
        for c in range(m):
            if not acted[c]:
                continue
            t2 = twin[c]
            if t2 >= 0 and acted[t2] and owner[cv[t2]] < owner[cv[c]]:
                continue      # the twin acts; this one follows it below
            p = cv[c]
            i = owner[p]
            j = owner[ce[c]]
            tx, tz, gap = geo[c, 0], geo[c, 1], geo[c, 2]
            nx, nz = tz, -tx
            px, pz = X[p, 0], X[p, 1]
            if crush:
                fn = kn_c[c] * (-gap - dp_c[c])
                if fn > cn_c[c]:                  # crushing: the excess closure is plastic
                    dp_new = -gap - cn_c[c] / kn_c[c]
                    work[4] += cn_c[c] * (dp_new - dp_c[c])
                    dp_c[c] = dp_new
                    fn = cn_c[c]
            else:
                fn = -kn_c[c] * gap
            # relative velocity of the vertex against block j at the contact point
            vix = vel[i, 0] - om[i] * (pz - pos[i, 1])
            viz = vel[i, 1] + om[i] * (px - pos[i, 0])
            vjx = vel[j, 0] - om[j] * (pz - pos[j, 1])
            vjz = vel[j, 1] + om[j] * (px - pos[j, 0])
            vt = (vix - vjx) * tx + (viz - vjz) * tz
            fs = fs_c[c] - ks_c[c] * vt * dt
            if not tied[c]:
                cap = fric * fn
                if abs(fs) > cap:
                    dsl = (abs(fs) - cap) / ks_c[c]
                    sl_c[c] += dsl
                    sg = 1.0 if fs > 0 else -1.0
                    w = 0.5 * (sg * fs_c[c] + cap) * dsl      # mean force × slip
                    fs = sg * cap
                    if fixed[i] or fixed[j]:
                        slip_base[i] = max(slip_base[i], sl_c[c])
                        slip_base[j] = max(slip_base[j], sl_c[c])
                        work[0] += w
                    elif abs(nz) > 0.9:
                        slip_bed[i] = max(slip_bed[i], sl_c[c])
                        slip_bed[j] = max(slip_bed[j], sl_c[c])
                        work[1 if px < fac_x else 2] += w
                    else:
                        work[3] += w
            fs_c[c] = fs
            if record:
                elastic += 0.5 * fn * fn / kn_c[c] + 0.5 * fs * fs / ks_c[c]
            fx = fn * nx + fs * tx
            fz = fn * nz + fs * tz
            F[i, 0] += fx
            F[i, 1] += fz
            F[i, 2] += (px - pos[i, 0]) * fz - (pz - pos[i, 1]) * fx
            F[j, 0] -= fx
            F[j, 1] -= fz
            F[j, 2] -= (px - pos[j, 0]) * fz - (pz - pos[j, 1]) * fx
        # twins that did not act carry the shear force of the one that did
        for c in range(m):
            t2 = twin[c]
            if t2 >= 0 and acted[c] and acted[t2] and owner[cv[t2]] < owner[cv[c]]:
                fs_c[c] = fs_c[t2]
                sl_c[c] = sl_c[t2]
                dp_c[c] = dp_c[t2]
        ke = 0.0
        pe = 0.0
        vmax = 0.0
        for b in range(n):
            if fixed[b]:
                continue
            if damping > 0.0:
                for d in range(2):
                    if vel[b, d] != 0.0:
                        F[b, d] -= damping * abs(F[b, d]) * (1.0 if vel[b, d] > 0 else -1.0)
                if om[b] != 0.0:
                    F[b, 2] -= damping * abs(F[b, 2]) * (1.0 if om[b] > 0 else -1.0)
            vx0, vz0, w0b = vel[b, 0], vel[b, 1], om[b]
            vel[b, 0] += dt * F[b, 0] * inv_m[b]
            vel[b, 1] += dt * F[b, 1] * inv_m[b]
            om[b] += dt * F[b, 2] * inv_I[b]
            if a_g != 0.0:
                work[5] -= dt * mass[b] * a_g * 0.5 * (vx0 + vel[b, 0])
            if record:
                ux, uz, uw = 0.5 * (vx0 + vel[b, 0]), 0.5 * (vz0 + vel[b, 1]), 0.5 * (w0b + om[b])
                ke += 0.5 * mass[b] * (ux * ux + uz * uz) + 0.5 * uw * uw / inv_I[b]
                pe += mass[b] * g * (pos[b, 1] - z_ref[b])
            sp = vel[b, 0] * vel[b, 0] + vel[b, 1] * vel[b, 1] + (om[b] * radius[b]) ** 2
            if sp > vmax:
                vmax = sp
            pos[b, 0] += dt * vel[b, 0]
            pos[b, 1] += dt * vel[b, 1]
            th[b] += dt * om[b]
        if record:
            rec[nrow, 0] = ag_t0 + step * dt
            rec[nrow, 1] = ke
            rec[nrow, 2] = pe
            rec[nrow, 3] = elastic
            if w0 >= 0:
                rec[nrow, 4] = pos[w0, 0] - dt * vel[w0, 0] - ref_pos[w0, 0]
                rec[nrow, 5] = th[w0] - dt * om[w0] - ref_th[w0]
            rec[nrow, 6] = work[0] + work[1] + work[2] + work[3] + work[4]
            rec[nrow, 7] = work[5]
            nrow += 1
        if check_every > 0 and (step + 1) % check_every == 0:
            if damping > 0.0 and math.sqrt(vmax) < vel_tol:
                status = 2
                break
            for b in range(n):
                if watch[b] and (ref_pos[b, 0] - pos[b, 0] > disp_limit
                                 or abs(th[b] - ref_th[b]) > rot_limit):
                    status = 1
            if status:
                break
    return (step + 1, status, nrow, key, cv, ce, kn_c, ks_c, fs_c, tied, sl_c, twin, cn_c, dp_c,
            builds)
