"""Task 3: first Lyapunov coefficient (Kuznetsov normalization), derivatives exact via sympy,
evaluation with mpmath at 30+ digits."""
import sympy as sp
import mpmath as mp

mp.mp.dps = 40
R = sp.Rational
s, v, th = sp.symbols('s v theta')


def mu_law(law, P):
    if law == 'ln2':
        return P['mu0'] + P['A']*sp.log(v) + P['B']*sp.log(th) + P['mu2']*sp.log(th)**2
    if law == 'cutoff':
        return P['mu0'] + P['A']*sp.log(v) + P['B']*sp.log(1 + th/P['thc'])
    raise ValueError


def muphi_of(law, P):
    nu = P['nu']
    if law == 'ln2':
        return P['B'] - 2*P['mu2']*sp.log(nu)
    return P['B']/(1 + nu*P['thc'])


def setup(law, P, inertial):
    """Return (F, X, x0, kappa_c, omega_c) with F a sympy vector field at kappa = kappa_c (exact)."""
    P = {k: sp.nsimplify(val) for k, val in P.items()}
    nu, A = P['nu'], P['A']
    mu = mu_law(law, P)
    mphi = muphi_of(law, P)
    m = P.get('m', 0)
    kc = (mphi - A)*(1 + m*nu**2/A)
    wc = nu*sp.sqrt(mphi/A - 1)
    s0 = mu.subs({v: nu, th: 1/nu})
    if inertial:
        F = sp.Matrix([kc*(nu - v), (s - mu)/m, 1 - v*th])
        X = [s, v, th]
        x0 = {s: s0, v: nu, th: 1/nu}
    else:
        vq = sp.exp((s - (mu - A*sp.log(v)))/A)
        F = sp.Matrix([kc*(nu - vq), 1 - vq*th])
        X = [s, th]
        x0 = {s: s0, th: 1/nu}
    return F, X, x0, kc, wc, mphi


def N(e):
    z = sp.N(e, 60)
    re_, im_ = z.as_real_imag()
    return mp.mpf(str(re_)) if im_ == 0 else mp.mpc(mp.mpf(str(re_)), mp.mpf(str(im_)))


def lyap(F, X, x0, wc_exact, verbose=False):
    n = len(X)
    # exact derivatives evaluated at x0
    J = mp.matrix(n, n)
    Bt = [[[None]*n for _ in range(n)] for _ in range(n)]
    Ct = [[[[None]*n for _ in range(n)] for _ in range(n)] for _ in range(n)]
    for i in range(n):
        for j in range(n):
            dij = sp.diff(F[i], X[j])
            J[i, j] = N(dij.subs(x0))
            for k in range(n):
                dijk = sp.diff(dij, X[k])
                Bt[i][j][k] = N(dijk.subs(x0))
                for l in range(n):
                    Ct[i][j][k][l] = N(sp.diff(dijk, X[l]).subs(x0))
    w = N(wc_exact)
    I = mp.mpc(0, 1)
    Bf = lambda x, y: mp.matrix([sum(Bt[i][j][k]*x[j]*y[k] for j in range(n) for k in range(n)) for i in range(n)])
    Cf = lambda x, y, z: mp.matrix([sum(Ct[i][j][k][l]*x[j]*y[k]*z[l] for j in range(n) for k in range(n) for l in range(n)) for i in range(n)])

    def nullvec(M):
        if n == 2:
            return mp.matrix([-M[0, 1], M[0, 0]])
        r1 = [M[0, j] for j in range(3)]; r2 = [M[1, j] for j in range(3)]
        return mp.matrix([r1[1]*r2[2]-r1[2]*r2[1], r1[2]*r2[0]-r1[0]*r2[2], r1[0]*r2[1]-r1[1]*r2[0]])
    Id = mp.eye(n)
    q = nullvec(J - I*w*Id)
    q = q/mp.sqrt(sum(abs(q[i])**2 for i in range(n)))
    p = nullvec(J.T + I*w*Id)
    ip = lambda a, b: sum(mp.conj(a[i])*b[i] for i in range(n))
    p = p/mp.conj(ip(p, q))
    assert abs(ip(p, q) - 1) < mp.mpf(10)**-35
    assert mp.norm(J*q - I*w*q) < mp.mpf(10)**-30, mp.norm(J*q - I*w*q)
    assert mp.norm(J.T*p + I*w*p) < mp.mpf(10)**-30
    qb = mp.matrix([mp.conj(x) for x in q])
    h11 = mp.lu_solve(J, Bf(q, qb))
    h20 = mp.lu_solve(2*I*w*Id - J, Bf(q, q))
    val = ip(p, Cf(q, q, qb)) - 2*ip(p, Bf(q, h11)) + ip(p, Bf(qb, h20))
    l1 = mp.re(val)/(2*w)
    c1 = val/2
    if verbose:
        print("  eig(J):", [mp.nstr(e, 20) for e in mp.eig(J)[0]])
    return l1, c1, q, p, J, w


mp.mp.dps = 40
cases = []
qs_base = dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu2=R('2.4e-4'))
cases.append(('(a) QS ln2 nu=1', 'ln2', dict(qs_base, nu=1), False))
cases.append(('(a) QS ln2 nu=10', 'ln2', dict(qs_base, nu=10), False))
cases.append(('(b) QS RR nu=1', 'ln2', dict(qs_base, mu2=0, nu=1), False))
cases.append(('(c) IN ln2 m=0.1 nu=3', 'ln2', dict(A=R('0.01'), B=R('0.02'), mu0=R('0.6'), mu2=R('5e-4'), m=R('0.1'), nu=3), True))
for mm in ['0.001', '0.01', '0.1', '1']:
    cases.append(('(d) IN RR m=%s nu=1' % mm, 'ln2', dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), mu2=0, m=R(mm), nu=1), True))
cut = dict(A=R('0.012'), B=R('0.023'), mu0=R('0.6'), thc=R('0.01'), m=R('1e-3'))
cases.append(('(e) IN cutoff thc=0.01 m=1e-3 nu=50', 'cutoff', dict(cut, nu=50), True))

if __name__ == '__main__':
    for name, law, P, inertial in cases:
        F, X, x0, kc, wc, mphi = setup(law, P, inertial)
        print(name)
        print("  mu_phi =", mp.nstr(N(mphi), 20), " mu_phi - mu_v =", mp.nstr(N(mphi - P['A']), 20))
        if N(mphi - P['A']) <= 0:
            print("  NO HOPF (mu_phi <= mu_v)"); continue
        l1, c1, q, p, J, w = lyap(F, X, x0, wc, verbose=True)
        print("  kappa_c =", mp.nstr(N(kc), 25))
        print("  omega_c =", mp.nstr(w, 25))
        print("  l1      =", mp.nstr(l1, 30))
        print("  Re c1   =", mp.nstr(mp.re(c1), 25), " Im c1 =", mp.nstr(mp.im(c1), 25))
        print("  |q_s|   =", mp.nstr(abs(q[0]), 25))
