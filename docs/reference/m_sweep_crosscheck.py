"""Independent cross-checks of m_sweep.py (output: m_sweep_crosscheck_out.txt via stdout redirect).

(a) RR law, small m.  Closed form of lim_{m->0} l1/m derived symbolically (sympy, exact in A, nu, w; m series of
    the exact c1 with Kuznetsov normalisation); compared with the numeric route of m_sweep.py at the m of the table
    and at m = 1e-40, 1e-60; the fit l1/m = c + d m over the table's small m is reported.
(b) ln2, nu = 1, m = 1e-2:
    (i)   the project's original l1 code t3_lyap.py (own tensors / eigenvectors / formula), at 60 digits;
    (ii)  nf.py order-5 normal form (route 2 in m_sweep_checks.txt: all rows);
    (iii) direct simulation (classical RK4 in double precision, pure Python) of the peak-to-peak amplitude of s at
          kappa = kappa_c (1 - eps), compared with C sqrt(kappa_c - kappa).
(c) m -> 0 limit vs the quasi-static model (t3_lyap.py, 2-D (s, theta) coordinates): l1_3D(m->0) = l1_QS |alpha|^2,
    alpha^2 = |q_s|^2 + |q_theta|^2 of the normalised 3-D q (the z-scalings differ by alpha); C has the same limit
    as the quasi-static closed form 4 sqrt(mu_phi (mu_phi - A)/mu2) (REPORT.md section 4).
(e) informative: Bautin point (l1 = 0) of the cutoff rows theta_c = 10, nu = 0.085.
(d) informative: relative error of l1, l2 when the same formulas are evaluated in (emulated) float64.
Usage (from /work/main): python3 docs/reference/m_sweep_crosscheck.py > docs/reference/m_sweep_crosscheck_out.txt
"""
import math
import os
import sys
import time

import mpmath as mp
import sympy as sp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import m_sweep as MS  # noqa: E402
import t3_lyap as T3  # noqa: E402  (sets mp.dps = 40 at import; reset below)

t_start = time.time()
RRbase = dict(A='0.012', B='0.023', mu0='0.5', mu2='0')


def row(law, Pstr, extra=30):
    S = MS.prepare(law, Pstr)
    W = 90 + int(3*max(0, -math.log10(float(S['P']['m'])))) + extra
    return MS.compute(S, W, False), S


# ------------------------------------------------------------------ (a) symbolic limit
print("(a) RR law: l1 = c m + d m^2 + ...  (m -> 0)")
m, A, nu, w = sp.symbols('m A nu w', positive=True)
Bsym = A*(1 + w**2/nu**2)               # eliminates B in favour of w = nu sqrt(B/A - 1)
s, v, th = sp.symbols('s v theta')
kc = (Bsym - A)*(1 + m*nu**2/A)
F = [kc*(nu - v), (s - A*sp.log(v) - Bsym*sp.log(th))/m, 1 - v*th]
X = [s, v, th]
x0 = {s: 0, v: nu, th: 1/nu}
J = sp.Matrix([[sp.diff(f, x).subs(x0) for x in X] for f in F])
I = sp.I


def T(i, *idx):
    e = F[i]
    for j in idx:
        e = sp.diff(e, X[j])
    return sp.simplify(e.subs(x0))


def Bf(a, b):
    return sp.Matrix([sum(T(i, j, k)*a[j]*b[k] for j in range(3) for k in range(3)) for i in range(3)])


def Cf(a, b, c):
    return sp.Matrix([sum(T(i, j, k, l)*a[j]*b[k]*c[l] for j in range(3) for k in range(3) for l in range(3))
                      for i in range(3)])


def conjv(x):  # all symbols real
    return x.applyfunc(lambda e: e.subs(I, -I))


M1 = J - I*w*sp.eye(3)
q = M1.row(0).cross(M1.row(2)).T      # unnormalised
M2 = J.T + I*w*sp.eye(3)
p = M2.row(0).cross(M2.row(2)).T
qb = conjv(q)
pq = (conjv(p).T*q)[0]
nq = sp.expand((conjv(q).T*q)[0])
h11 = J.LUsolve(Bf(q, qb))
h20 = (2*I*w*sp.eye(3) - J).LUsolve(Bf(q, q))
val = (conjv(p).T*(Cf(q, q, qb)/2 - Bf(q, h11) + Bf(qb, h20)/2))[0]
c1 = sp.together(val/(pq*nq))           # = c1 for q -> q/|q|, p -> p sqrt(nq)/conj(pq)
ser = sp.series(c1, m, 0, 3).removeO()
a0, a1, a2 = [ser.coeff(m, k) for k in range(3)]
re = lambda e: sp.simplify((e + e.subs(I, -I))/2)
re0 = re(a0)
c_sym = sp.factor(re(a1)/w)
d_sym = re(a2)/w
print("  Re c1(m=0) =", re0, "   (quasi-static plain RR: l1 = 0)")
print("  c = lim l1/m =", c_sym)
Asym, Bs = sp.symbols('A B', positive=True)
c_AB = Bs*nu**3*sp.sqrt(nu**2*(Bs/Asym - 1))/(2*Asym**2*(1 + Bs*nu**4/Asym + Bs*(Bs - Asym)*nu**2))
diff = sp.simplify(c_sym.subs(w, nu*sp.sqrt(Bs/Asym - 1)).subs(A, Asym) - c_AB)
print("  equivalently c = B nu^3 w / (2 A^2 (1 + B nu^4/A + B (B - A) nu^2)),  w = nu sqrt(B/A - 1)   [difference:", diff, "]")
print("  symbolic part took %.0f s" % (time.time() - t_start))

mp.mp.dps = 80
for (Av, Bv, nuv, ms, label) in [('0.012', '0.023', '1', ['1e-6', '1e-8', '1e-9', '1e-10', '1e-11', '1e-12', '1e-13',
                                                          '1e-14', '1e-40', '1e-60'], 'RR nu=1'),
                                 ('0.012', '0.023', '3', ['1e-6', '1e-10', '1e-12', '1e-14', '1e-60'], 'RR nu=3'),
                                 ('0.012', '0.023', '0.2', ['1e-6', '1e-10', '1e-12', '1e-14', '1e-60'], 'RR nu=0.2'),
                                 ('0.008', '0.012', '1', ['2e-11', '1e-60'], 'granite nu=1'),
                                 ('0.008', '0.012', '10', ['2e-9', '1e-60'], 'granite nu=10')]:
    sub = {A: sp.Rational(Av), nu: sp.Rational(nuv), w: sp.Rational(nuv)*sp.sqrt(sp.Rational(Bv)/sp.Rational(Av) - 1)}
    cex = sp.N(c_sym.subs(sub), 100)
    dex = sp.N(d_sym.subs(sub), 60)
    print("  %s: c = %s   (exact: %s)" % (label, sp.N(cex, 55), sp.nsimplify(c_sym.subs(sub))))
    print("        d = %s  (m^2 coefficient, from the same series)" % sp.N(dex, 25))
    data = []
    for mm in ms:
        r, S = row('RR', dict(A=Av, B=Bv, mu0='0.5', mu2='0', nu=nuv, m=mm))
        mp.mp.dps = 200
        cm = mp.mpf(str(cex))
        ratio = r['l1']/mp.mpf(sp.Rational(mm).p)*mp.mpf(sp.Rational(mm).q)
        mf = mp.mpf(sp.Rational(mm).p)/mp.mpf(sp.Rational(mm).q)
        data.append((mf, ratio))
        print("     m=%-6s l1=%s  l1/m=%s  (l1/m-c)/m=%s  |l1/m - c - d m|/c=%s" % (
            mm, mp.nstr(r['l1'], 16), mp.nstr(ratio, 22), mp.nstr((ratio - cm)/mf, 12),
            mp.nstr(abs(ratio - cm - mp.mpf(str(dex))*mf)/cm, 3)))
    small = [(a, b) for a, b in data if mp.mpf('1e-16') < a <= mp.mpf('1e-8')]
    if len(small) >= 3:
        # least-squares line l1/m = c_fit + d_fit m over the table's m <= 1e-8 (independent of the symbolic result)
        n = len(small)
        sx = mp.fsum(a for a, _ in small); sy = mp.fsum(b for _, b in small)
        sxx = mp.fsum(a*a for a, _ in small); sxy = mp.fsum(a*b for a, b in small)
        dfit = (n*sxy - sx*sy)/(n*sxx - sx*sx)
        cfit = (sy - dfit*sx)/n
        print("     LSQ fit over m<=1e-8 rows: c_fit=%s (rel.diff to exact %s), d_fit=%s" % (
            mp.nstr(cfit, 25), mp.nstr(abs(cfit - mp.mpf(str(cex)))/mp.mpf(str(cex)), 3), mp.nstr(dfit, 15)))
    sys.stdout.flush()

# ------------------------------------------------------------------ (b) ln2, nu = 1, m = 1e-2
print("\n(b) ln2 A=0.012 B=0.023 mu2=2.4e-4 nu=1 m=1e-2")
P = dict(A='0.012', B='0.023', mu0='0.5', mu2='2.4e-4', nu='1', m='1e-2')
r, S = row('ln2', P)
mp.mp.dps = 60
F3, X3, x03, kc3, wc3, mphi3 = T3.setup('ln2', dict(A=sp.Rational('0.012'), B=sp.Rational('0.023'), mu0=sp.Rational('0.5'),
                                                    mu2=sp.Rational('2.4e-4'), nu=1, m=sp.Rational('1e-2')), True)
l1b, c1b, qb3, pb3, Jb, wb = T3.lyap(F3, X3, x03, wc3)
print("  (i) t3_lyap.py (60 digits): l1 =", mp.nstr(l1b, 50))
print("      m_sweep.py            : l1 =", mp.nstr(r['l1'], 50))
print("      rel.diff l1 = %s, rel.diff c1 = %s, rel.diff |q_s| = %s" % (
    mp.nstr(abs(l1b - r['l1'])/abs(r['l1']), 3), mp.nstr(abs(c1b - r['c1'])/abs(r['c1']), 3),
    mp.nstr(abs(abs(qb3[0]) - r['qs'])/r['qs'], 3)))
print("  (ii) nf.py route: see m_sweep_checks.txt (route2 c1/c2 agreement on every row)")
# (iii) simulation
Af, Bf_, mu2f, nuf, mf = 0.012, 0.023, 2.4e-4, 1.0, 1e-2
kcf = float(r['kc'])
Cf_ = float(r['C'])
wf = float(r['w'])


def rhs(x, kap):
    s_, v_, t_ = x
    lt = math.log(t_)
    mu = 0.5 + Af*math.log(v_) + Bf_*lt + mu2f*lt*lt
    return (kap*(nuf - v_), (s_ - mu)/mf, 1 - v_*t_)


def rk4(x, kap, dt):
    k1 = rhs(x, kap)
    k2 = rhs([x[i] + 0.5*dt*k1[i] for i in range(3)], kap)
    k3 = rhs([x[i] + 0.5*dt*k2[i] for i in range(3)], kap)
    k4 = rhs([x[i] + dt*k3[i] for i in range(3)], kap)
    return [x[i] + dt/6*(k1[i] + 2*k2[i] + 2*k3[i] + k4[i]) for i in range(3)]


mp.mp.dps = 60
Kq = MS.kuznetsov(MS.num_tensors(S['Tex'], 60), mp.mpf(str(sp.N(S['wc'], 75))), with_l2=False)
qv = [complex(z) for z in Kq['q']]
s0 = 0.5  # mu(nu, 1/nu) at nu = 1
print("  (iii) direct RK4 simulation, dt = 2pi/w/1000; Delta_s = peak-to-peak of s over the last 10 periods")
for eps in [4e-2, 1e-2, 4e-3]:
    kap = kcf*(1 - eps)
    dk = kcf - kap
    lamr = float(mp.re(r['lam_p']))
    zabs = math.sqrt(abs(lamr*(-dk)/float(mp.re(r['c1']))))
    x = [s0 + 2*(zabs*qv[0]).real, 1 + 2*(zabs*qv[1]).real, 1 + 2*(zabs*qv[2]).real]
    Tper = 2*math.pi/wf
    dt = Tper/1000
    sigma = abs(lamr*dk)           # linear growth rate at the steady state
    ttot = 12/(2*sigma) + 10*Tper  # amplitude deviations decay like exp(-2 sigma t)
    nsteps = int(ttot/dt)
    nlast = int(10*Tper/dt)
    smin, smax = 1e9, -1e9
    for k in range(nsteps):
        x = rk4(x, kap, dt)
        if k >= nsteps - nlast:
            smin = min(smin, x[0]); smax = max(smax, x[0])
    pred = Cf_*math.sqrt(dk)
    print("     eps=%-6g t=%.0f  Delta_s(sim)=%.10g  C sqrt(kc-k)=%.10g  ratio=%.6f" % (
        eps, ttot, smax - smin, pred, (smax - smin)/pred))
    sys.stdout.flush()

# ------------------------------------------------------------------ (c) m -> 0 vs quasi-static
print("\n(c) m -> 0 limit of the inertial ln2 rows vs the quasi-static model (t3_lyap.py, (s, theta) coordinates)")
for nuv in ['1', '10']:
    mp.mp.dps = 60
    Pq = dict(A=sp.Rational('0.012'), B=sp.Rational('0.023'), mu0=sp.Rational('0.5'), mu2=sp.Rational('2.4e-4'),
              nu=sp.Rational(nuv))
    Fq, Xq, x0q, kcq, wcq, mphiq = T3.setup('ln2', Pq, False)
    l1q, c1q, qq, pq_, Jq, wq = T3.lyap(Fq, Xq, x0q, wcq)
    mu_phi = mp.mpf(str(sp.N(mphiq, 70)))
    Cqs = 4*mp.sqrt(mu_phi*(mu_phi - mp.mpf('0.012'))/mp.mpf('2.4e-4'))
    for mm in ['1e-14', '1e-40', '1e-60']:
        r3, S3 = row('ln2', dict(A='0.012', B='0.023', mu0='0.5', mu2='2.4e-4', nu=nuv, m=mm))
        alpha2 = abs(r3['q'][0])**2 + abs(r3['q'][2])**2
        mp.mp.dps = 60
        print("  nu=%s m=%-6s l1_3D=%s  l1_QS*alpha^2=%s  rel.diff=%s" % (
            nuv, mm, mp.nstr(r3['l1'], 22), mp.nstr(l1q*alpha2, 22), mp.nstr(abs(r3['l1'] - l1q*alpha2)/abs(l1q*alpha2), 3)))
        print("                  C_3D=%s  C_QS(closed form)=%s  rel.diff=%s" % (
            mp.nstr(r3['C'], 22), mp.nstr(Cqs, 22), mp.nstr(abs(r3['C'] - Cqs)/Cqs, 3)))
# ------------------------------------------------------------------ (d) float64 emulation (informative)
print("\n(d) How much of l1, l2 survives a float64 evaluation of the same formulas (cancellation in c1):")
print("    tensors rounded to double, whole Kuznetsov pipeline at mpmath prec = 53 bits (an emulation, not IEEE-exact)")
for law, Pstr in MS.cases():
    S = MS.prepare(law, Pstr)
    hi = MS.compute(S, 140, False)
    mp.mp.prec = 53
    Td = {k: [mp.mpf(float(x)) for x in vals] for k, vals in MS.num_tensors(S['Tex'], 20).items()}
    wd = mp.mpf(float(sp.N(S['wc'], 20)))
    K = MS.kuznetsov(Td, wd, with_l2=True)
    mp.mp.dps = 140
    print("  %-6s nu=%-5s m=%-6s term_scale/|l1|=%-9s  rel.err(float64) l1=%-8s l2=%-8s" % (
        law, Pstr['nu'], Pstr['m'], mp.nstr(hi['ts']/abs(hi['l1']), 3),
        mp.nstr(abs(mp.re(K['c1'])/wd - hi['l1'])/abs(hi['l1']), 2),
        mp.nstr(abs(mp.re(K['c2'])/wd - hi['l2'])/abs(hi['l2']), 2)))
    sys.stdout.flush()
# ------------------------------------------------------------------ (e) sign change of l1 in the cutoff rows
print("\n(e) cutoff law, theta_c = 10, nu = 0.085: l1 < 0 at m = 1e-2, > 0 at m = 1 -> Bautin point m_B in between")


def row_cut(mm):
    S = MS.prepare('cutoff', dict(A='0.012', B='0.023', mu0='0.5', thc='10', nu='0.085', m=mp.nstr(mm, 75)))
    r = MS.compute(S, 90, False)
    mp.mp.dps = 90
    return r


def l1_cut(mm):
    return row_cut(mm)['l1']


mp.mp.dps = 90
for mm in ['0.02', '0.1', '0.5', '1']:
    print("   m=%-5s l1=%s" % (mm, mp.nstr(l1_cut(mp.mpf(mm)), 15)))
mB = mp.findroot(l1_cut, (mp.mpf('0.6'), mp.mpf('0.9')), solver='secant', tol=mp.mpf(10)**-140)
rB = row_cut(mB)
print("   m_B = %s   (l1(m_B) = %s)" % (mp.nstr(mB, 50), mp.nstr(rB['l1'], 3)))
print("   kappa_c(m_B) = %s  omega_c = %s" % (mp.nstr(rB['kc'], 30), mp.nstr(rB['w'], 30)))
print("   l2(m_B) = %s" % mp.nstr(rB['l2'], 30))
print("\nruntime %.0f s" % (time.time() - t_start))
