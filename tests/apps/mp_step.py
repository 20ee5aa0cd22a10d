"""The exact step response shared by the analysis checks (reference_check.py,
long_horizon_check.py): e^{M dt} of the augmented controllable companion matrix
M = [A b; 0 0] of num/den in mpmath, then its powers, at equally spaced t. Exact to far
below double rounding at `dps` digits (issue 28: SciPy's lsim drifts over long horizons
and loses a stiff system's slow mode)."""
import mpmath


def augmented_companion(num, den):
    """[A b; 0 0] of the controllable companion realisation of num/den in mpmath, and c, d."""
    den = [mpmath.mpf(float(x)) for x in den]
    num = [mpmath.mpf(float(x)) for x in num]
    den, num = [x / den[0] for x in den], [x / den[0] for x in num]
    n = len(den) - 1
    num = [mpmath.mpf(0)] * (n + 1 - len(num)) + num
    m = mpmath.zeros(n + 1, n + 1)
    for j in range(n):
        m[0, j] = -den[j + 1]
    for i in range(1, n):
        m[i, i - 1] = 1
    m[0, n] = 1
    return m, [num[j + 1] - num[0] * den[j + 1] for j in range(n)], num[0], n


def step_samples(num, den, t, dps):
    """y(t_k) as floats, t equally spaced from t[0] (the response starts at rest there)."""
    with mpmath.workdps(dps):
        m, c, d, n = augmented_companion(num, den)
        e = mpmath.expm(m * (mpmath.mpf(t[1]) - mpmath.mpf(t[0]))) if len(t) > 1 else None
        z = mpmath.zeros(n + 1, 1)
        z[n] = 1
        y = []
        for _ in t:
            y.append(float(sum(c[j] * z[j] for j in range(n)) + d))
            z = e * z
        return y
