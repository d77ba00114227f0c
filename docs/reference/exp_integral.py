"""Issue 27 (soft adhesive contacts): reference values of Schallamach's
lifetime function g(z) = e^z E1(z) (seed Appendix D, eq. D7) and its
derivatives g^(k)(z), k = 0..5, at 40 digits, for src/exp_integral.rs.

mpmath's own e1 and numerical differentiation at 60 digits (mp.diff), not
the series, continued fraction or recurrence of the Rust code. The
derivatives are checked against the recurrence g' = g - 1/z here too.

Columns: z, g, g', g'', g''', g'''', g''''' (then E1(z) where z <= 700).
Run: python3 exp_integral.py > exp_integral_out.txt
"""
import mpmath as mp

mp.mp.dps = 60


def g(z):
    return mp.exp(z) * mp.e1(z)


def main():
    zs = []
    for e in range(-8, 3):
        for m in (1, 2, 5):
            zs.append(mp.mpf(m) * mp.mpf(10) ** e)
    zs += [mp.mpf(x) for x in ("0.9999", "1.0001", "1.5", "3.7", "700", "1000")]
    zs = sorted(set(zs))
    print("# z g g1 g2 g3 g4 g5 E1")
    for z in zs:
        ds = [mp.diff(g, z, k) for k in range(6)]
        assert abs(ds[1] - (ds[0] - 1 / z)) < mp.mpf(10) ** -40 * abs(ds[1]) + mp.mpf(10) ** -50
        e1 = mp.e1(z) if z <= 700 else mp.mpf(0)
        print(" ".join(mp.nstr(x, 40, min_fixed=-1, max_fixed=-1) for x in [z] + ds + [e1]))


if __name__ == "__main__":
    main()
