"""Reference table of Hopf normal-form coefficients of the inertial rate-and-state block across the mass m.

    ds/dt = kappa (nu - v),  dv/dt = (s - mu(v, theta))/m,  dtheta/dt = 1 - v theta,   x = (s, v, theta)

Laws: RR (mu2 = 0), ln2 (+ mu2 ln^2 theta), cutoff (B ln(1 + theta/theta_c)).
Normalisation (Kuznetsov 1998): J q = i w q, J^T p = -i w p, conj(q).q = 1, conj(p).q = 1.
    c1 = 1/2 <p,C(q,q,qb)> - <p,B(q,J^-1 B(q,qb))> + 1/2 <p,B(qb,(2iw-J)^-1 B(q,q))>,  l1 = Re c1 / w
    c2 = G32/12 (Kuznetsov's explicit multilinear formula, h21 normalised by <p,h21> = 0),  l2 = Re c2 / w
    C  = 4 |q_s| sqrt|Re lambda'(kappa) / Re c1|   (peak-to-peak of s ~ C sqrt|kappa - kappa_c|)
    l1_term_scale = (|t1| + |t2| + |t3|)/w  with t1, t2, t3 the three terms of c1 above.

Route 1 (reported): exact sympy derivatives (parameters as exact rationals of the decimal strings) -> mpmath,
explicit Kuznetsov formulas (generalisation of l2/kuz_l2.py to any law and parameter set).
Every row is computed at two working precisions (W and W + 30 digits, W >= 90 and growing with log10(1/m));
the digits on which they agree are reported (>= 50 required).
Route 2 (every row): the generic order-5 normal-form solver of l2/nf.py (polynomial substitution, no closed
formulas), with the eigenvector phase rotated by 0.37 pi -> c1, c2.
Route 3 (every row, l1 only): the same vector field in logarithmic coordinates y = (s, ln v, ln theta);
c1 is invariant under the near-identity part, and its linear part D = diag(1, 1/nu, nu) gives
c1_x = c1_y |D q_x|^2.
Other checks per row: |Re lambda| of the critical pair at kappa_c (mp.eig) < 1e-45; kappa_c from the Routh-Hurwitz
condition a2 a1 = a0 of the numerically evaluated Jacobian vs the closed form; omega_c = Im lambda; mu_phi from
the derivative; lambda' = -conj(p_s) q_v vs the closed-form transversality formula.

Usage (from /work/main):  python3 docs/reference/m_sweep.py > docs/reference/m_sweep.csv
stdout: CSV with 20 significant digits.  Also written next to this file: m_sweep_full.csv (50 significant digits)
and m_sweep_checks.txt (per-row diagnostics).  Progress goes to stderr.
"""
import itertools
import math
import os
import sys
import time

import mpmath as mp
import sympy as sp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, 'l2'))
from nf import TaylorEval, normal_form, jacobian  # noqa: E402  (project's own generic normal-form solver)

R = sp.Rational
s, v, th = sp.symbols('s v theta')
X = [s, v, th]
I = mp.mpc(0, 1)


def Q(x):
    """Exact rational from a decimal string, e.g. '0.012' -> 3/250, '1e-14' -> 1/10^14."""
    return sp.Rational(x)


# ------------------------------------------------------------------ model
def mu_expr(law, P, vv, tt):
    base = P['mu0'] + P['A']*sp.log(vv)
    if law == 'RR':
        return base + P['B']*sp.log(tt)
    if law == 'ln2':
        return base + P['B']*sp.log(tt) + P['mu2']*sp.log(tt)**2
    if law == 'cutoff':
        return base + P['B']*sp.log(1 + tt/P['thc'])
    raise ValueError(law)


def muphi_closed(law, P):
    nu = P['nu']
    if law == 'RR':
        return P['B']
    if law == 'ln2':
        return P['B'] - 2*P['mu2']*sp.log(nu)
    return P['B']/(1 + nu*P['thc'])


def field(law, P, kappa):
    mu = mu_expr(law, P, v, th)
    return [kappa*(P['nu'] - v), (s - mu)/P['m'], 1 - v*th]


def field_log(law, P, kappa):
    """Same field in y = (s, a, b) = (s, ln v, ln theta)."""
    a, b = sp.symbols('a b')
    V, T = sp.exp(a), sp.exp(b)
    mu = mu_expr(law, P, V, T)
    return [kappa*(P['nu'] - V), (s - mu)/P['m']/V, (1 - V*T)/T], [s, a, b]


def exact_tensors(F, Xs, x0, maxdeg):
    """{sorted index tuple: [exact sympy value of d^k F_i / dx_idx at x0, i=0..n-1]} for 1 <= k <= maxdeg."""
    n = len(Xs)
    T = {}
    cache = {(): list(F)}
    for order in range(1, maxdeg + 1):
        for key in itertools.combinations_with_replacement(range(n), order):
            parent = cache[key[:-1]]
            d = [sp.diff(e, Xs[key[-1]]) for e in parent]
            cache[key] = d
            T[key] = [e.subs(x0) for e in d]
    return T


def num_tensors(Tex, dps):
    out = {}
    for key, vals in Tex.items():
        out[key] = [mp.mpf(0) if e == 0 else mp.mpf(str(sp.N(e, dps + 15))) for e in vals]
    return out


# ------------------------------------------------------------------ linear algebra
def cj(x):
    return mp.matrix([mp.conj(a) for a in x])


def ip(a, b):
    return mp.fsum(mp.conj(a[i])*b[i] for i in range(len(a)))


def vnorm(x):
    return mp.sqrt(mp.fsum(abs(a)**2 for a in x))


def kern3(M):
    """Kernel of a corank-1 3x3 matrix: best-conditioned cross product of two rows."""
    best = None
    for r1, r2 in [(0, 1), (0, 2), (1, 2)]:
        a = [M[r1, j] for j in range(3)]
        b = [M[r2, j] for j in range(3)]
        c = mp.matrix([a[1]*b[2] - a[2]*b[1], a[2]*b[0] - a[0]*b[2], a[0]*b[1] - a[1]*b[0]])
        sc = vnorm(c)/(vnorm(a)*vnorm(b))
        if best is None or sc > best[0]:
            best = (sc, c)
    return best[1]


def form(T, *vecs):
    k = len(vecs)
    out = [mp.mpc(0)]*3
    for idx in itertools.product(range(3), repeat=k):
        t = T[tuple(sorted(idx))]
        if t[0] == 0 and t[1] == 0 and t[2] == 0:
            continue
        prod = mp.mpc(1)
        for a, j in enumerate(idx):
            prod *= vecs[a][j]
        out = [out[i] + t[i]*prod for i in range(3)]
    return mp.matrix(out)


def jac_of(T):
    J = mp.matrix(3, 3)
    for i in range(3):
        for j in range(3):
            J[i, j] = T[(j,)][i]
    return J


def hopf_qp(J, w):
    Id = mp.eye(3)
    q = kern3(J - I*w*Id)
    q = q/vnorm(q)
    p = kern3(J.T + I*w*Id)
    p = p/mp.conj(ip(p, q))
    return q, p


# ------------------------------------------------------------------ route 1: Kuznetsov formulas
def kuznetsov(T, w, with_l2=True):
    J = jac_of(T)
    Id = mp.eye(3)
    q, p = hopf_qp(J, w)
    nJ = mp.mnorm(J, 1)
    res_q = mp.norm(J*q - I*w*q)/nJ
    res_p = mp.norm(J.T*p + I*w*p)/(nJ*vnorm(p))
    qb = cj(q)
    Bf = lambda a, b: form(T, a, b)
    Cf = lambda a, b, c: form(T, a, b, c)
    Df = lambda a, b, c, d: form(T, a, b, c, d)
    Ef = lambda a, b, c, d, e: form(T, a, b, c, d, e)
    Bqq, Bqqb = Bf(q, q), Bf(q, qb)
    h20 = mp.lu_solve(2*I*w*Id - J, Bqq)
    h02 = cj(h20)
    h11 = -mp.lu_solve(J, Bqqb)
    Cqqqb = Cf(q, q, qb)
    t1 = ip(p, Cqqqb)/2
    t2 = ip(p, Bf(q, h11))          # = -<p, B(q, J^-1 B(q,qb))>
    t3 = ip(p, Bf(qb, h20))/2
    c1 = t1 + t2 + t3
    G21 = 2*c1
    out = dict(J=J, q=q, p=p, c1=c1, t=(t1, t2, t3), res_q=res_q, res_p=res_p)
    if not with_l2:
        return out
    r21 = Cqqqb + Bf(qb, h20) + 2*Bf(q, h11)
    h30 = mp.lu_solve(3*I*w*Id - J, Cf(q, q, q) + 3*Bf(q, h20))
    Mb = mp.matrix(4, 4)
    rb = mp.matrix(4, 1)
    for a in range(3):
        for b in range(3):
            Mb[a, b] = (I*w*Id - J)[a, b]
        Mb[a, 3] = q[a]
        Mb[3, a] = mp.conj(p[a])
        rb[a] = (r21 - G21*q)[a]
    sol = mp.lu_solve(Mb, rb)
    h21 = mp.matrix([sol[0], sol[1], sol[2]])
    h12 = cj(h21)
    h31 = mp.lu_solve(2*I*w*Id - J, Df(q, q, q, qb) + 3*Cf(q, q, h11) + 3*Cf(q, qb, h20) + 3*Bf(h20, h11)
                      + Bf(qb, h30) + 3*Bf(q, h21) - 3*G21*h20)
    h22 = -mp.lu_solve(J, Df(q, q, qb, qb) + 4*Cf(q, qb, h11) + Cf(qb, qb, h20) + Cf(q, q, h02) + 2*Bf(h11, h11)
                       + 2*Bf(q, h12) + 2*Bf(qb, h21) + Bf(h20, h02) - 2*(G21 + mp.conj(G21))*h11)
    G32 = ip(p, Ef(q, q, q, qb, qb) + Df(q, q, q, h02) + 6*Df(q, q, qb, h11) + 3*Df(q, qb, qb, h20)
             + 6*Cf(q, h11, h11) + 3*Cf(q, h20, h02) + 6*Cf(q, qb, h21) + 3*Cf(q, q, h12) + 6*Cf(qb, h20, h11)
             + Cf(qb, qb, h30) + 6*Bf(h11, h21) + 3*Bf(h20, h12) + Bf(h02, h30) + 3*Bf(q, h22) + 2*Bf(qb, h31))
    out.update(c2=G32/12, border=sol[3])
    return out


# ------------------------------------------------------------------ one row
def prepare(law, Pstr):
    """Exact setup, independent of working precision."""
    P = {k: Q(val) for k, val in Pstr.items()}
    P.setdefault('mu2', R(0))
    nu, A, m = P['nu'], P['A'], P['m']
    mphi = muphi_closed(law, P)
    kc = (mphi - A)*(1 + m*nu**2/A)
    wc = nu*sp.sqrt(mphi/A - 1)
    x0 = {s: mu_expr(law, P, nu, 1/nu), v: nu, th: 1/nu}
    F = field(law, P, kc)
    Tex = exact_tensors(F, X, x0, 5)
    # Jacobian with symbolic kappa for the Routh-Hurwitz check (independent of the closed-form kappa_c)
    kap = sp.Symbol('kappa')
    Jk = sp.Matrix([[sp.diff(e, xx).subs(x0) for xx in X] for e in field(law, P, kap)])
    mphi_num = (th*sp.diff(mu_expr(law, P, v, th), th)).subs(x0)
    Fl, Y = field_log(law, P, kc)
    y0 = {Y[0]: x0[s], Y[1]: sp.log(nu), Y[2]: -sp.log(nu)}
    Tlog = exact_tensors(Fl, Y, y0, 3)
    # symbolic Taylor data for route 2 (nf.py), kappa already exact
    return dict(P=P, mphi=mphi, kc=kc, wc=wc, x0=x0, F=F, Tex=Tex, Jk=Jk, kap=kap, mphi_num=mphi_num, Tlog=Tlog)


def compute(S, dps, full_checks):
    mp.mp.dps = dps
    P = S['P']
    nu, A, m = P['nu'], P['A'], P['m']
    T = num_tensors(S['Tex'], dps)
    w = mp.mpf(str(sp.N(S['wc'], dps + 15)))
    kc = mp.mpf(str(sp.N(S['kc'], dps + 15)))
    K = kuznetsov(T, w)
    q, p, c1, c2 = K['q'], K['p'], K['c1'], K['c2']
    lam_p = -mp.conj(p[0])*q[1]            # d lambda / d kappa = <p, dJ/dkappa q>, dJ/dkappa = -e_s e_v^T
    C = 4*abs(q[0])*mp.sqrt(abs(mp.re(lam_p)/mp.re(c1)))
    r = dict(kc=kc, w=w, l1=mp.re(c1)/w, l2=mp.re(c2)/w, C=C, ts=sum(abs(t) for t in K['t'])/w,
             c1=c1, c2=c2, lam_p=lam_p, qs=abs(q[0]), q=q)
    if not full_checks:
        return r
    chk = {}
    chk['res_q'], chk['res_p'] = K['res_q'], K['res_p']
    chk['border'] = abs(K['border'])
    # eigenvalues at kappa_c
    ev = mp.eig(K['J'])[0]
    crit = [e for e in ev if abs(mp.im(e)) > w/2]
    chk['max_abs_Re_crit'] = max(abs(mp.re(e)) for e in crit)
    chk['Im_crit_minus_w'] = min(abs(abs(mp.im(e)) - w) for e in crit)/w
    chk['third_eig'] = [e for e in ev if abs(mp.im(e)) <= w/2][0]
    # Routh-Hurwitz kappa_c from the numeric Jacobian (affine in kappa)
    def coeffs(kv):
        Jn = mp.matrix(3, 3)
        for i in range(3):
            for j in range(3):
                Jn[i, j] = mp.mpf(str(sp.N(S['Jk'][i, j].subs(S['kap'], kv), dps + 15)))
        a2 = -(Jn[0, 0] + Jn[1, 1] + Jn[2, 2])
        a1 = (Jn[0, 0]*Jn[1, 1] - Jn[0, 1]*Jn[1, 0] + Jn[0, 0]*Jn[2, 2] - Jn[0, 2]*Jn[2, 0]
              + Jn[1, 1]*Jn[2, 2] - Jn[1, 2]*Jn[2, 1])
        a0 = -mp.det(Jn)
        return a2*a1 - a0
    h0, h1 = coeffs(0), coeffs(1)
    kc_rh = -h0/(h1 - h0)
    chk['kc_RH_rel'] = abs(kc_rh - kc)/kc
    chk['muphi_rel'] = abs(mp.mpf(str(sp.N(S['mphi_num'], dps + 15))) - mp.mpf(str(sp.N(S['mphi'], dps + 15)))) \
        / mp.mpf(str(sp.N(S['mphi'], dps + 15)))
    # closed-form transversality (REPORT.md section 1, mu_phi general)
    mu_v = mp.mpf(str(sp.N(A, dps + 15)))
    nun = mp.mpf(str(sp.N(nu, dps + 15)))
    mm = mp.mpf(str(sp.N(m, dps + 15)))
    a2 = mu_v/nun + mm*nun
    rel_cf = -(mu_v/nun)/(2*(a2**2 + mm**2*w**2))
    iml_cf = (nun*a2 + mm*w**2)/(2*w*(a2**2 + mm**2*w**2))
    chk['lamp_closed_rel'] = abs(lam_p - mp.mpc(rel_cf, iml_cf))/abs(lam_p)
    # route 2: nf.py (generic polynomial-substitution normal form), q phase rotated by 0.37 pi
    Tnf = [[] for _ in range(3)]
    for key, vals in T.items():
        alpha = [0, 0, 0]
        for j in key:
            alpha[j] += 1
        fac = mp.mpf(1)
        for a_ in alpha:
            fac *= mp.factorial(a_)
        for i in range(3):
            if vals[i] != 0:
                Tnf[i].append((tuple(alpha), vals[i]/fac))
    qr = q*mp.expjpi(mp.mpf('0.37'))
    pr = p*mp.expjpi(mp.mpf('0.37'))
    g, H, info = normal_form(Tnf, w, qr, pr, order=5)
    chk['route2_c1_rel'] = abs(g[(2, 1)] - c1)/abs(c1)
    chk['route2_l2_rel'] = abs(mp.re(g[(3, 2)]) - mp.re(c2))/abs(mp.re(c2))
    chk['route2_c2_rel'] = abs(g[(3, 2)] - c2)/abs(c2)
    # route 3: log coordinates, l1 only
    Tl = num_tensors(S['Tlog'], dps)
    Kl = kuznetsov(Tl, w, with_l2=False)
    Dq = mp.matrix([q[0], q[1]/nun, q[2]*nun])
    c1_from_log = Kl['c1']*vnorm(Dq)**2
    chk['route3_c1_rel'] = abs(c1_from_log - c1)/abs(c1)
    chk['route3_ts_log'] = sum(abs(t) for t in Kl['t'])/w
    r['chk'] = chk
    return r


# ------------------------------------------------------------------ cases
def cases():
    out = []
    mlist = ['1e3', '1e2', '10', '1', '0.1', '1e-2', '1e-4', '1e-6', '1e-8', '1e-9', '1e-10', '1e-11', '1e-12',
             '1e-13', '1e-14']
    base = dict(A='0.012', B='0.023', mu0='0.5')
    for mm in mlist:
        out.append(('RR', dict(base, mu2='0', nu='1', m=mm)))
    for nu in ['3', '0.2']:
        for mm in ['1e-6', '1e-10', '1e-12', '1e-14']:
            out.append(('RR', dict(base, mu2='0', nu=nu, m=mm)))
    for mm in mlist:
        out.append(('ln2', dict(base, mu2='2.4e-4', nu='1', m=mm)))
    for mm in ['1e-2', '1e-10', '1e-14']:
        out.append(('ln2', dict(base, mu2='2.4e-4', nu='10', m=mm)))
    for mm in ['1e3', '10', '1', '1e-2', '1e-6', '1e-10', '1e-14']:
        out.append(('cutoff', dict(base, thc='10', nu='0.085', m=mm)))
    for mm in ['1', '1e-6', '1e-12']:
        out.append(('cutoff', dict(base, thc='0.01', nu='1', m=mm)))
    # Slow driving: the age phi = 1/nu spans decades (Newton must converge on
    # the frequency ~ nu, not only on phi)
    for nu in ['1e-3', '1e-6', '1e-7', '1e-9']:
        for mm in ['1e-2', '1e-10']:
            out.append(('ln2', dict(base, mu2='2.4e-4', nu=nu, m=mm)))
    for nu in ['1e-6', '1e-3']:
        out.append(('cutoff', dict(base, thc='4.583333333333333e-4', nu=nu, m='2.5e-7')))
    gran = dict(A='0.008', B='0.012', mu0='0.7', mu2='0')
    out.append(('RR', dict(gran, nu='10', m='2e-9')))
    out.append(('RR', dict(gran, nu='1', m='2e-11')))
    return out


def sci(x, nd):
    """x in %.{nd-1}e style, computed from the mpf directly (no double rounding through float)."""
    x = mp.mpf(x)
    if x == 0:
        return '%.*e' % (nd - 1, 0.0)
    sgn = '-' if x < 0 else ''
    x = abs(x)
    e = int(mp.floor(mp.log10(x)))
    mant = mp.nint(x/mp.mpf(10)**(e - nd + 1))
    if mant >= mp.mpf(10)**nd:
        e += 1
        mant = mp.nint(x/mp.mpf(10)**(e - nd + 1))
    digs = str(int(mant))
    return '%s%s.%se%+03d' % (sgn, digs[0], digs[1:], e)


def agree_digits(a, b):
    if a == b:
        return 999
    return float(-mp.log10(abs(a - b)/abs(a)))


HEADER = 'law,A,B,mu0,mu2,theta_c,nu,m,kappa_c,omega_c,l1,l2,C,l1_term_scale'


def main():
    t0 = time.time()
    rows20, rows50, log = [HEADER], [HEADER], []
    worst = dict(digits=1e9)
    for law, Pstr in cases():
        t1 = time.time()
        S = prepare(law, Pstr)
        mlog = max(0, -math.log10(float(S['P']['m'])))
        W = 90 + int(3*mlog)
        lo = compute(S, W, True)
        hi = compute(S, W + 30, False)
        mp.mp.dps = W + 30
        dig = {k: agree_digits(hi[k], lo[k]) for k in ('kc', 'w', 'l1', 'l2', 'C', 'ts')}
        mind = min(dig.values())
        chk = lo['chk']
        assert chk['max_abs_Re_crit'] < mp.mpf(10)**-45, chk['max_abs_Re_crit']
        assert chk['kc_RH_rel'] < mp.mpf(10)**-50 and chk['muphi_rel'] < mp.mpf(10)**-50
        assert mind >= 50, dig
        worst['digits'] = min(worst['digits'], mind)
        P = S['P']
        lead = [law, Pstr['A'], Pstr['B'], Pstr['mu0'], Pstr.get('mu2', '0'), Pstr.get('thc', ''),
                Pstr['nu'], Pstr['m']]
        vals = [hi['kc'], hi['w'], hi['l1'], hi['l2'], hi['C'], hi['ts']]
        rows20.append(','.join(lead + [sci(x, 20) for x in vals]))
        rows50.append(','.join(lead + [sci(x, 50) for x in vals]))
        e = lambda x: mp.nstr(x, 3)
        log.append('%s %s' % (law, ' '.join('%s=%s' % kv for kv in Pstr.items())))
        log.append('  W=%d/%d  agreeing digits (W vs W+30): %s' % (W, W + 30, ', '.join('%s %.0f' % kv for kv in dig.items())))
        log.append('  kappa_c=%s  omega_c=%s  third eig=%s' % (mp.nstr(hi['kc'], 25), mp.nstr(hi['w'], 25),
                                                               mp.nstr(chk['third_eig'], 20)))
        log.append('  c1=%s  c2=%s' % (mp.nstr(hi['c1'], 25), mp.nstr(hi['c2'], 25)))
        log.append('  l1=%s  l2=%s  C=%s  l1_term_scale=%s  |l1|/scale=%s' % (
            mp.nstr(hi['l1'], 25), mp.nstr(hi['l2'], 25), mp.nstr(hi['C'], 25), mp.nstr(hi['ts'], 10),
            e(abs(hi['l1'])/hi['ts'])))
        log.append("  lambda'=%s  |q_s|=%s" % (mp.nstr(hi['lam_p'], 25), mp.nstr(hi['qs'], 25)))
        log.append('  checks: |Re lam_crit|=%s |Im-w|/w=%s kc(RH)-kc rel=%s mu_phi rel=%s lambda\'(closed) rel=%s '
                   'res_q=%s res_p=%s border=%s' % (e(chk['max_abs_Re_crit']), e(chk['Im_crit_minus_w']),
                                                    e(chk['kc_RH_rel']), e(chk['muphi_rel']),
                                                    e(chk['lamp_closed_rel']), e(chk['res_q']), e(chk['res_p']),
                                                    e(chk['border'])))
        log.append('  route2 (nf.py, phase 0.37pi): c1 rel=%s  Re c2 rel=%s  c2 rel=%s ;  route3 (log coords) c1 '
                   'rel=%s' % (e(chk['route2_c1_rel']), e(chk['route2_l2_rel']), e(chk['route2_c2_rel']),
                               e(chk['route3_c1_rel'])))
        for k in ('route2_c1_rel', 'route2_l2_rel', 'route3_c1_rel', 'lamp_closed_rel'):
            worst[k] = max(worst.get(k, 0), chk[k])
        print('%-6s nu=%-5s m=%-6s W=%d  %.1fs  min digits %.0f  l1=%s' % (law, Pstr['nu'], Pstr['m'], W,
              time.time() - t1, mind, mp.nstr(hi['l1'], 12)), file=sys.stderr)
        sys.stderr.flush()
    print('\n'.join(rows20))
    with open(os.path.join(HERE, 'm_sweep_full.csv'), 'w') as f:
        f.write('\n'.join(rows50) + '\n')
    summary = ['SUMMARY: min agreeing digits over all rows/quantities = %.0f' % worst['digits']] + \
        ['  worst %s = %s' % (k, mp.nstr(val, 3)) for k, val in worst.items() if k != 'digits'] + \
        ['  runtime %.0f s' % (time.time() - t0)]
    with open(os.path.join(HERE, 'm_sweep_checks.txt'), 'w') as f:
        f.write('\n'.join(log + [''] + summary) + '\n')
    print('\n'.join(summary), file=sys.stderr)


if __name__ == '__main__':
    main()
