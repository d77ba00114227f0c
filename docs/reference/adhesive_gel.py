"""Issue 27 (soft adhesive contacts): reference values for the built-in
gel scene (examples/scenes/gel.toml) and a scene written from scratch
(tests/adhesive.rs), at 40 digits, independent of the Rust code: mpmath's
e1, findroot and numerical differentiation (mp.diff) of the steady friction
written out from the seed's equations.

Dimensionless (docs/model.md, "Soft adhesive contacts"): u = v / V_s,
z = 1/u, g(z) = e^z E1(z), T(u) = z g(z) (eq. D7), n_ss = T / (T + r)
(eq. D2), F_ss(u) = n_ss g(1/u) + f_v u^(1 - alpha).

- V_max, V_c: the zeros of dF_ss/du (maximum, then minimum), times V_s.
- kappa_c = -(1/r + 1/T(nu)) dF_ss/du (nu) and
  Omega_c^2 = kappa_c (1/r + 1/T) / F_u, F_u = d/du [n g(1/u) +
  f_v u^(1-alpha)] at fixed n = n_ss; checked here against the eigenvalues
  of the 2x2 Jacobian of the field (s, n) built by mp.diff, with u slaved
  by findroot: at kappa_c they are +-i Omega_c.

- With the block's inertia (mass M, m = M V_s / (F_a tau_out)):
  chi = m lambda_n / F_u, kappa_c_inertial = kappa_c (1 + chi) and
  Omega_c_inertial^2 = kappa_c_inertial lambda_n / (F_u + m lambda_n)
  (docs/model.md, "Linear stability"), checked here against the
  eigenvalues of the 3x3 Jacobian of the field (s, u, n), m du/dt =
  s - F(n, u), built by mp.diff: at kappa_c_inertial two are
  +-i Omega_c_inertial.

Run: python3 adhesive_gel.py > adhesive_gel_out.txt
"""
import mpmath as mp

mp.mp.dps = 40


def g(z):
    return mp.exp(z) * mp.e1(z)


def T(u):
    return (1 / u) * g(1 / u)


def force(u, n, fv, alpha):
    return n * g(1 / u) + fv * u ** (1 - alpha)


def nss(u, r):
    return T(u) / (T(u) + r)


def Fss(u, r, fv, alpha):
    return force(u, nss(u, r), fv, alpha)


def case(name, r, fv, alpha, nu, Vs_um_s, Fa, tau_out, guesses, M):
    dF = lambda u: mp.diff(lambda x: Fss(x, r, fv, alpha), u)
    u_max = mp.findroot(dF, guesses[0])
    u_min = mp.findroot(dF, guesses[1])
    assert mp.diff(dF, u_max) < 0 and mp.diff(dF, u_min) > 0
    lam = 1 / r + 1 / T(nu)
    kappa_c = -lam * dF(nu)
    n0 = nss(nu, r)
    F_u = mp.diff(lambda x: force(x, n0, fv, alpha), nu)
    omega_c = mp.sqrt(kappa_c * lam / F_u)

    def field(s, n):
        u = mp.findroot(lambda x: force(x, n, fv, alpha) - s, nu)
        return [kappa_c * (nu - u), (1 - n) / r - n / T(u)]

    s0 = Fss(nu, r, fv, alpha)
    J = mp.matrix(2, 2)
    for i in range(2):
        J[i, 0] = mp.diff(lambda a: field(a, n0)[i], s0)
        J[i, 1] = mp.diff(lambda a: field(s0, a)[i], n0)
    ev = mp.eig(J)[0]
    assert all(abs(mp.re(e)) < mp.mpf(10) ** -20 * abs(e) for e in ev), ev
    assert abs(abs(mp.im(ev[0])) / omega_c - 1) < mp.mpf(10) ** -20
    # With inertia: the 3x3 Jacobian of (s, u, n) at steady sliding.
    m = M * Vs_um_s * 1e-6 / (Fa * tau_out)
    chi = m * lam / F_u
    kappa_in = kappa_c * (1 + chi)
    omega_in = mp.sqrt(kappa_in * lam / (F_u + m * lam))

    def inertial(x):
        s, u, n = x
        return [kappa_in * (nu - u), (s - force(u, n, fv, alpha)) / m,
                (1 - n) / r - n / T(u)]

    x0 = [s0, nu, n0]
    Ji = mp.matrix(3, 3)
    for j in range(3):
        for i in range(3):
            def fi(a, i=i, j=j):
                y = list(x0)
                y[j] = a
                return inertial(y)[i]
            Ji[i, j] = mp.diff(fi, x0[j])
    evi = mp.eig(Ji)[0]
    hopf = [e for e in evi if abs(mp.re(e)) < mp.mpf(10) ** -15 * abs(e)]
    assert len(hopf) == 2, evi
    assert abs(abs(mp.im(hopf[0])) / omega_in - 1) < mp.mpf(10) ** -15, (hopf, omega_in)
    print(f"[{name}]")
    for k, v in [("V_max_um_s", u_max * Vs_um_s), ("V_c_um_s", u_min * Vs_um_s),
                 ("F_max_N", Fss(u_max, r, fv, alpha) * Fa),
                 ("F_min_N", Fss(u_min, r, fv, alpha) * Fa),
                 ("kappa_c", kappa_c), ("omega_c", omega_c),
                 ("K_c_N_m", kappa_c * Fa / (Vs_um_s * 1e-6 * tau_out)),
                 ("steady_force_N", s0 * Fa), ("steady_bonds", n0),
                 ("chi", chi), ("kappa_c_inertial", kappa_in),
                 ("omega_c_inertial", omega_in),
                 ("K_c_inertial_N_m", kappa_in * Fa / (Vs_um_s * 1e-6 * tau_out))]:
        print(k, mp.nstr(v, 25))


# examples/scenes/gel.toml: F_a = 0.05 N, V_s = 0.025 um/s, tau_out = 1 s,
# tau_on = 0.1 s, F_v = 5e-4 N, alpha = 0.6, V = 20 um/s, M = 1 g.
case("gel", mp.mpf("0.1"), mp.mpf("0.01"), mp.mpf("0.6"), mp.mpf(800),
     mp.mpf("0.025"), mp.mpf("0.05"), mp.mpf(1), (26, 3800), mp.mpf("1e-3"))
# tests/adhesive.rs's scene written from scratch: a Newtonian junction,
# F_a = 0.2 N, V_s = 0.1 um/s, tau_out = 2 s, tau_on = 0.6 s,
# F_v = 2e-5 N, alpha = 0, V = 5 um/s, M = 2 g.
case("newtonian", mp.mpf("0.3"), mp.mpf("1e-4"), mp.mpf(0), mp.mpf(50),
     mp.mpf("0.1"), mp.mpf("0.2"), mp.mpf(2), (12, 950), mp.mpf("2e-3"))
