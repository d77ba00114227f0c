"""Independent route: Kuznetsov's explicit multilinear formulas (Kuznetsov 1999 SIAM J Numer Anal 36; Elements 3rd ed
§8.7) for G21, G32 with derivative tensors B, C, D, E computed directly from exact sympy derivatives.
Does not use nf.py except for nothing -- all code here is separate (own eigenvectors, own tensors).
  h20 = (2iwI-A)^{-1} B(q,q);  h11 = -A^{-1} B(q,qb)
  G21 = <p, C(q,q,qb) + B(qb,h20) + 2B(q,h11)>
  h30 = (3iwI-A)^{-1}[C(q,q,q) + 3B(q,h20)]
  h21 : (iwI-A) h21 = C(q,q,qb) + B(qb,h20) + 2B(q,h11) - G21 q,  <p,h21> = 0
  h31 = (2iwI-A)^{-1}[D(q,q,q,qb) + 3C(q,q,h11) + 3C(q,qb,h20) + 3B(h20,h11) + B(qb,h30) + 3B(q,h21) - 3G21 h20]
  h22 = -A^{-1}[D(q,q,qb,qb) + 4C(q,qb,h11) + C(qb,qb,h20) + C(q,q,h02) + 2B(h11,h11) + 2B(q,h12) + 2B(qb,h21)
               + B(h20,h02) - 2(G21+conj G21) h11]
  G32 = <p, E(q,q,q,qb,qb) + D(q,q,q,h02) + 6D(q,q,qb,h11) + 3D(q,qb,qb,h20) + 6C(q,h11,h11) + 3C(q,h20,h02)
            + 6C(q,qb,h21) + 3C(q,q,h12) + 6C(qb,h20,h11) + C(qb,qb,h30) + 6B(h11,h21) + 3B(h20,h12)
            + B(h02,h30) + 3B(q,h22) + 2B(qb,h31)>          (terms with <p,h21> dropped: zero by normalisation)
  l1 = Re G21/(2w), l2 = Re G32/(12w)."""
import itertools
import sympy as sp
import mpmath as mp

mp.mp.dps = 40
R = sp.Rational
s, v, th = sp.symbols('s v theta')
X = [s, v, th]
A, B, mu0 = R('0.012'), R('0.023'), R('0.6')


def tensors(nu, m):
    nu = sp.Integer(nu)
    kc = (B - A)*(1 + m*nu**2/A)
    F = [kc*(nu - v), (s - mu0 - A*sp.log(v) - B*sp.log(th))/m, 1 - v*th]
    x0 = {s: mu0 + (A - B)*sp.log(nu), v: nu, th: 1/nu}
    T = {}
    for order in range(1, 6):
        for idx in itertools.product(range(3), repeat=order):
            key = tuple(sorted(idx))
            if key in T:
                continue
            vals = []
            for i in range(3):
                e = F[i]
                for j in key:
                    e = sp.diff(e, X[j])
                vals.append(mp.mpf(sp.N(e.subs(x0), 60)) if e != 0 else mp.mpf(0))
            T[key] = vals
    return T, kc


def form(T, *vecs):
    k = len(vecs)
    out = [mp.mpc(0)]*3
    for idx in itertools.product(range(3), repeat=k):
        t = T[tuple(sorted(idx))]
        if all(x == 0 for x in t):
            continue
        prod = mp.mpc(1)
        for a, j in enumerate(idx):
            prod *= vecs[a][j]
        if prod == 0:
            continue
        out = [out[i] + t[i]*prod for i in range(3)]
    return mp.matrix(out)


def cj(x):
    return mp.matrix([mp.conj(a) for a in x])


def ip(a, b):
    return mp.fsum(mp.conj(a[i])*b[i] for i in range(3))


def l2_kuznetsov(nu, m_str):
    m = sp.Rational(m_str)
    T, kc = tensors(nu, m)
    Am = mp.matrix(3, 3)
    for i in range(3):
        for j in range(3):
            Am[i, j] = T[(j,)][i]
    w = mp.mpf(nu)*mp.sqrt(mp.mpf(23)/12 - 1)
    I = mp.mpc(0, 1)
    Id = mp.eye(3)
    # eigenvectors by explicit cross product of two rows
    def kern(M):
        r1 = [M[0, j] for j in range(3)]; r2 = [M[2, j] for j in range(3)]
        return mp.matrix([r1[1]*r2[2]-r1[2]*r2[1], r1[2]*r2[0]-r1[0]*r2[2], r1[0]*r2[1]-r1[1]*r2[0]])
    q = kern(Am - I*w*Id); q = q/mp.sqrt(mp.re(ip(q, q)))
    p = kern(Am.T + I*w*Id); p = p/mp.conj(ip(p, q))
    assert mp.norm(Am*q - I*w*q) < 1e-33 and mp.norm(Am.T*p + I*w*p) < 1e-33
    qb = cj(q)
    Bf = lambda a, b: form(T, a, b)
    Cf = lambda a, b, c: form(T, a, b, c)
    Df = lambda a, b, c, d: form(T, a, b, c, d)
    Ef = lambda a, b, c, d, e: form(T, a, b, c, d, e)
    h20 = mp.lu_solve(2*I*w*Id - Am, Bf(q, q)); h02 = cj(h20)
    h11 = -mp.lu_solve(Am, Bf(q, qb))
    r21 = Cf(q, q, qb) + Bf(qb, h20) + 2*Bf(q, h11)
    G21 = ip(p, r21)
    h30 = mp.lu_solve(3*I*w*Id - Am, Cf(q, q, q) + 3*Bf(q, h20))
    Mb = mp.matrix(4, 4); rb = mp.matrix(4, 1)
    for a in range(3):
        for b in range(3):
            Mb[a, b] = (I*w*Id - Am)[a, b]
        Mb[a, 3] = q[a]; Mb[3, a] = mp.conj(p[a]); rb[a] = (r21 - G21*q)[a]
    sol = mp.lu_solve(Mb, rb)
    h21 = mp.matrix([sol[0], sol[1], sol[2]]); h12 = cj(h21)
    h31 = mp.lu_solve(2*I*w*Id - Am, Df(q, q, q, qb) + 3*Cf(q, q, h11) + 3*Cf(q, qb, h20) + 3*Bf(h20, h11)
                      + Bf(qb, h30) + 3*Bf(q, h21) - 3*G21*h20)
    h22 = -mp.lu_solve(Am, Df(q, q, qb, qb) + 4*Cf(q, qb, h11) + Cf(qb, qb, h20) + Cf(q, q, h02) + 2*Bf(h11, h11)
                       + 2*Bf(q, h12) + 2*Bf(qb, h21) + Bf(h20, h02) - 2*(G21 + mp.conj(G21))*h11)
    G32 = ip(p, Ef(q, q, q, qb, qb) + Df(q, q, q, h02) + 6*Df(q, q, qb, h11) + 3*Df(q, qb, qb, h20)
             + 6*Cf(q, h11, h11) + 3*Cf(q, h20, h02) + 6*Cf(q, qb, h21) + 3*Cf(q, q, h12) + 6*Cf(qb, h20, h11)
             + Cf(qb, qb, h30) + 6*Bf(h11, h21) + 3*Bf(h20, h12) + Bf(h02, h30) + 3*Bf(q, h22) + 2*Bf(qb, h31))
    return dict(kc=kc, w=w, G21=G21, G32=G32, l1=mp.re(G21)/(2*w), l2=mp.re(G32)/(12*w), border=sol[3])


if __name__ == '__main__':
    for nu, mstr in [(1, '0.0016140505108687765218922615553'), (3, '0.000179338945652086280210251283922'),
                     (1, '0.001')]:
        r = l2_kuznetsov(nu, mstr)
        print("nu=%d m=%s" % (nu, mstr))
        print("   l1 = Re G21/(2w) =", mp.nstr(r['l1'], 10), "  G21/2 =", mp.nstr(r['G21']/2, 25))
        print("   G32/12 =", mp.nstr(r['G32']/12, 30))
        print("   l2 = Re G32/(12 w) =", mp.nstr(r['l2'], 30), "  (bordered mult", mp.nstr(abs(r['border']), 3), ")")
