"""Generic Poincare normal form on the centre manifold of a Hopf point, any order, by direct
polynomial substitution (no closed-form Kuznetsov formulas are used).

Invariance equation  d/dt H(z, zb) = F(x0 + H(z, zb)),   zdot = g(z, zb),
  H(z, zb) = q z + conj(q) zb + sum_{j+k>=2} H[j,k] z^j zb^k            (plain coefficients, no factorials)
  g(z, zb) = i w z + g[2,1] z^2 zb + g[3,2] z^3 zb^2 + ...               (resonant terms only)
Normalisation: J q = i w q, J^T p = -i w p, conj(q).q = 1, conj(p).q = 1, <p, H[m+1,m]> = 0.
Hence c1 = g[2,1], c2 = g[3,2]; Kuznetsov's G21 = 2 c1, G32 = 12 c2; l1 = Re c1 / w, l2 = Re c2 / w.

Taylor coefficients of F at x0 are exact (sympy) and evaluated in mpmath.
"""
import itertools
import sympy as sp
import mpmath as mp


# ---------------------------------------------------------------- Taylor data
def multi_indices(n, maxdeg):
    out = []
    for d in range(1, maxdeg + 1):
        for c in itertools.combinations_with_replacement(range(n), d):
            a = [0]*n
            for i in c:
                a[i] += 1
            out.append(tuple(a))
    return out


def taylor_symbolic(F, X, maxdeg):
    """Return list over components of list of (alpha, sympy expr of d^alpha F_i / alpha!) (not yet at x0)."""
    n = len(X)
    res = []
    for i in range(len(F)):
        terms = []
        for a in multi_indices(n, maxdeg):
            e = F[i]
            fact = 1
            for j in range(n):
                if a[j]:
                    e = sp.diff(e, X[j], a[j])
                    fact *= sp.factorial(a[j])
            if e != 0:
                terms.append((a, e/fact))
        res.append(terms)
    return res


def taylor_numeric(Tsym, X, params, x0fun, pvals):
    """Evaluate symbolic Taylor data at x0 (x0fun(pvals) -> list of mp values), params -> pvals (mp)."""
    x0v = x0fun(pvals)
    args = list(X) + list(params)
    vals = list(x0v) + list(pvals)
    out = []
    for terms in Tsym:
        ct = []
        for a, e in terms:
            f = sp.lambdify(args, e, 'mpmath')
            c = mp.mpmathify(f(*vals))
            if c != 0:
                ct.append((a, c))
        out.append(ct)
    return out


class TaylorEval:
    """Cache lambdified Taylor coefficients so they can be re-evaluated quickly for many parameter values."""

    def __init__(self, F, X, params, x0fun, maxdeg=5):
        self.X, self.params, self.x0fun = X, params, x0fun
        T = taylor_symbolic(F, X, maxdeg)
        args = list(X) + list(params)
        self.T = [[(a, sp.lambdify(args, e, 'mpmath')) for a, e in terms] for terms in T]
        self.n = len(X)

    def __call__(self, pvals):
        vals = list(self.x0fun(pvals)) + list(pvals)
        out = []
        for terms in self.T:
            out.append([(a, mp.mpmathify(f(*vals))) for a, f in terms])
        return out


def jacobian(T, n):
    J = mp.matrix(n, n)
    for i, terms in enumerate(T):
        for a, c in terms:
            if sum(a) == 1:
                J[i, a.index(1)] = c
    return J


# ---------------------------------------------------------------- polynomials in (z, zb)
def pmul(a, b, N):
    r = {}
    for (j1, k1), c1 in a.items():
        for (j2, k2), c2 in b.items():
            if j1 + k1 + j2 + k2 <= N:
                key = (j1 + j2, k1 + k2)
                r[key] = r.get(key, 0) + c1*c2
    return r


def padd(a, b, s=1):
    r = dict(a)
    for k, c in b.items():
        r[k] = r.get(k, 0) + s*c
    return r


# ---------------------------------------------------------------- linear algebra helpers
def nullvec(M):
    """kernel vector of an n x n matrix of corank 1 (via SVD-free approach: solve with one fixed component)."""
    n = M.rows
    best = None
    for fix in range(n):
        idx = [i for i in range(n) if i != fix]
        # drop each row in turn, choose best conditioned
        for drop in range(n):
            rows = [i for i in range(n) if i != drop]
            Ms = mp.matrix(n - 1, n - 1)
            rhs = mp.matrix(n - 1, 1)
            for ii, r in enumerate(rows):
                for jj, c in enumerate(idx):
                    Ms[ii, jj] = M[r, c]
                rhs[ii] = -M[r, fix]
            try:
                sol = mp.lu_solve(Ms, rhs)
            except ZeroDivisionError:
                continue
            v = mp.matrix(n, 1)
            v[fix] = 1
            for jj, c in enumerate(idx):
                v[c] = sol[jj]
            res = mp.norm(M*v)/mp.norm(v)
            if best is None or res < best[0]:
                best = (res, v)
    return best[1]


def inner(a, b):  # <a, b> = conj(a) . b
    return mp.fsum(mp.conj(a[i])*b[i] for i in range(len(a)))


def conjv(a):
    return mp.matrix([mp.conj(x) for x in a])


def hopf_vectors(J, w, phase=0):
    n = J.rows
    I = mp.mpc(0, 1)
    q = nullvec(J - I*w*mp.eye(n))
    q = q/mp.sqrt(inner(q, q).real)
    q = q*mp.expjpi(phase)  # arbitrary phase (result must not depend on it)
    p = nullvec(J.T + I*w*mp.eye(n))
    p = p/mp.conj(inner(p, q))
    return q, p


# ---------------------------------------------------------------- normal form
def compose(T, Hy, N):
    """F(x0 + y) with y_i = Hy[i] (polys in z, zb), truncated at total degree N. Returns list of polys."""
    n = len(Hy)
    # powers
    pw = [[{(0, 0): mp.mpf(1)}] for _ in range(n)]
    for i in range(n):
        for e in range(1, N + 1):
            pw[i].append(pmul(pw[i][-1], Hy[i], N))
    out = []
    for terms in T:
        acc = {}
        for a, c in terms:
            if sum(a) > N:  # every y_i is O(|z|), so such monomials are beyond degree N
                continue
            mono = {(0, 0): mp.mpf(1)}
            for i in range(n):
                if a[i]:
                    mono = pmul(mono, pw[i][a[i]], N)
            for k, v in mono.items():
                acc[k] = acc.get(k, 0) + c*v
        out.append(acc)
    return out


def normal_form(T, w, q, p, order=5, check=True):
    """Return (g, H, info). g: dict of resonant coefficients g[(m+1,m)]; H: dict (j,k) -> vector."""
    n = q.rows
    J = jacobian(T, n)
    I = mp.mpc(0, 1)
    qb = conjv(q)
    H = {(1, 0): q, (0, 1): qb}
    g = {(1, 0): I*w}
    info = {}
    for N in range(2, order + 1):
        Hy = [dict(((j, k), H[(j, k)][i]) for (j, k) in H) for i in range(n)]
        rhs = compose(T, Hy, N)
        zdot = dict(g)
        zbdot = {(k, j): mp.conj(c) for (j, k), c in g.items()}
        # LHS = sum_i H_jk (j z^{j-1} zb^k zdot + k z^j zb^{k-1} zbdot)
        lhs = [dict() for _ in range(n)]
        for (j, k), h in H.items():
            pz = {}
            if j:
                pz = padd(pz, pmul({(j - 1, k): mp.mpf(j)}, zdot, N))
            if k:
                pz = padd(pz, pmul({(j, k - 1): mp.mpf(k)}, zbdot, N))
            for i in range(n):
                for key, c in pz.items():
                    lhs[i][key] = lhs[i].get(key, 0) + h[i]*c
        for j in range(N, -1, -1):
            k = N - j
            if j < k:
                break
            R = mp.matrix([rhs[i].get((j, k), 0) - lhs[i].get((j, k), 0) for i in range(n)])
            M = I*w*(j - k)*mp.eye(n) - J
            if j - k == 1:
                G = inner(p, R)
                g[(j, k)] = G
                # bordered system [[M, q],[conj(p)^T, 0]] [h; s] = [R - G q; 0]
                Mb = mp.matrix(n + 1, n + 1)
                rb = mp.matrix(n + 1, 1)
                for a in range(n):
                    for b in range(n):
                        Mb[a, b] = M[a, b]
                    Mb[a, n] = q[a]
                    Mb[n, a] = mp.conj(p[a])
                    rb[a] = R[a] - G*q[a]
                sol = mp.lu_solve(Mb, rb)
                h = mp.matrix([sol[a] for a in range(n)])
                info[(j, k, 'border_s')] = sol[n]
            else:
                h = mp.lu_solve(M, R)
            H[(j, k)] = h
            if j != k:
                H[(k, j)] = conjv(h)
    return g, H, info
