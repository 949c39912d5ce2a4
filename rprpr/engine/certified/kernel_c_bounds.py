"""The hand-written C of ``rprpr/_kernel.c``'s ``bounds`` (``kernel_gen`` writes the
file): what one pass proves per box, after the numpy lines of ``bounds/assembly.py``
(``_assemble``, ``_settled``), the same IEEE operations in the same order;
tests/engine/bounds/test_assembly.py holds the two together bit for bit."""

BOUNDS = r"""
/* What one pass proves per box (assembly.py's ``_assemble`` and ``_settled``: the same
 * IEEE operations, in the same order, as their numpy lines; assembly.py calls it).
 * bounds(Pm, Pr, where, Bm, Br, Dm, Dr, rad, lo, hi, t_last, limit, out, n): P the
 * torques (2 rows) at the m distinct ends, where[j], where[n + j] the columns of box j's
 * ends lo[j], hi[j] among them, B and D the torques and their derivatives over the n
 * boxes (2 rows), rad the boxes' radii; every array C-contiguous, float64 (where: the
 * platform's Py_ssize_t). limit None: out holds 11 planes of 2 x n doubles (low, low_t,
 * up, floor, the six ends, monotone as 0/1); limit (L1, L2): out holds n doubles, 1 for
 * a box settled on its side of the limits before the forms near instants, else 0.
 * True when done, False when an array is not one it takes (numpy's path then runs). */
static double up_abs(double m, double r)
{
    double u = fabs(m) + r;
    u = u * GROW;
    u = u + PAD;
    return isfinite(u) ? u : INFINITY;
}
static double low_abs(double m, double r)
{
    double l = fabs(m) - r;
    l = l * DOWN;
    return (isfinite(l) && l > 0) ? l : 0.0;
}
static double low_of(double m, double r)
{
    double l = m - r;
    double e = fabs(l) * FOURU;
    l = l - e;
    l = l - PAD;
    return isfinite(l) ? l : -INFINITY;
}
static double up_of(double m, double r)
{
    double h = m + r;
    double e = fabs(h) * FOURU;
    h = h + e;
    h = h + PAD;
    return isfinite(h) ? h : INFINITY;
}

static int take_c(PyObject *o, Py_buffer *v, Py_ssize_t *got, Py_ssize_t len, int index)
{
    if (PyObject_GetBuffer(o, v, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        return 1;
    }
    (*got)++;
    const char *f = v->format;
    if (f == NULL || v->len != 8 * len || v->itemsize != 8)
        return 1;
    if (index)
        return !(sizeof(Py_ssize_t) == 8 && (strcmp(f, "l") == 0 || strcmp(f, "q") == 0
                                             || strcmp(f, "n") == 0));
    return !(strcmp(f, "d") == 0 || strcmp(f, "=d") == 0);
}

static PyObject *py_bounds(PyObject *self, PyObject *args)
{
    PyObject *o[10], *limit, *out;
    double t_last, L[2] = {0.0, 0.0};
    Py_ssize_t n, m, j;
    int i, settled;
    if (!PyArg_ParseTuple(args, "OOOOOOOOOOdOOn", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5],
                          &o[6], &o[7], &o[8], &o[9], &t_last, &limit, &out, &n))
        return NULL;
    settled = limit != Py_None;
    if (settled && !PyArg_ParseTuple(limit, "dd", &L[0], &L[1]))
        return NULL;
    Py_buffer views[10], ov;
    Py_ssize_t got = 0;
    int bad = 0;
    if (n < 0 || take_out(out, &ov, settled ? n : 22 * n) < 0)
        return NULL;
    if (PyObject_GetBuffer(o[0], &views[0], PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyErr_Clear();
        return done(views, got, &ov, 1);
    }
    got++;
    m = views[0].len / 16; /* P: 2 x m */
    Py_ssize_t lens[10] = {2 * m, 2 * m, 2 * n, 2 * n, 2 * n, 2 * n, 2 * n, n, n, n};
    PyBuffer_Release(&views[0]);
    got = 0;
    for (i = 0; i < 10 && !bad; i++)
        bad = take_c(o[i], &views[i], &got, lens[i], i == 2);
    if (bad)
        return done(views, got, &ov, 1);
    const double *Pm = views[0].buf, *Pr = views[1].buf, *Bm = views[3].buf,
                 *Br = views[4].buf, *Dm = views[5].buf, *Dr = views[6].buf,
                 *rad = views[7].buf, *lo = views[8].buf, *hi = views[9].buf;
    const Py_ssize_t *where = views[2].buf;
    for (j = 0; j < 2 * n; j++)
        if (where[j] < 0 || where[j] >= m)
            return done(views, got, &ov, 1);
    double *res = ov.buf;
    for (j = 0; j < n; j++) {
        int all = 1;
        double width = 2.0 * rad[j], hw = 0.5 * width;
        int va = lo[j] <= t_last, vb = hi[j] <= t_last;
        for (i = 0; i < 2; i++) {
            Py_ssize_t k = i * n + j, a = i * m + where[j], b = i * m + where[n + j];
            double pam = Pm[a], par = Pr[a], pbm = Pm[b], pbr = Pr[b];
            double ua = up_abs(pam, par), ub = up_abs(pbm, pbr);
            double t, u, cm, cr, am, ar;
            double mv = ua + ub;
            t = up_abs(Dm[k], Dr[k]) * width;
            mv = mv + t;
            mv = mv * 0.5;
            mv = mv * GROW;
            mv = mv + PAD;
            double up = nanmin(up_abs(Bm[k], Br[k]), mv);
            /* around = pa + D * Ball(hw, hw): Ball's product, then its sum */
            cm = Dm[k] * hw;
            t = fabs(Dm[k]) + Dr[k]; t = t * hw; u = Dr[k] * fabs(hw); t = t + u;
            u = fabs(cm) * U; u = u + ETA; t = t + u; t = t * GROW; cr = t + PAD;
            am = pam + cm;
            t = par + cr; u = fabs(am) * U; t = t + u; t = t * GROW; ar = t + PAD;
            double floor = nanmax(low_abs(Bm[k], Br[k]), low_abs(am, ar));
            if (settled) {
                all = all && ((up <= L[i]) || (floor > L[i]));
                continue;
            }
            double la = va ? low_abs(pam, par) : 0.0, lb = vb ? low_abs(pbm, pbr) : 0.0;
            int mono = low_abs(Dm[k], Dr[k]) > 0 && isfinite(ua) && isfinite(ub);
            up = mono ? nanmin(up, nanmax(ua, ub)) : up;
            int same = (mono && low_of(pam, par) > 0 && low_of(pbm, pbr) > 0)
                       || (mono && up_of(pam, par) < 0 && up_of(pbm, pbr) < 0);
            floor = same ? nanmax(floor, nanmin(la, lb)) : floor;
            Py_ssize_t N = 2 * n;
            res[k] = nanmax(la, lb);
            res[N + k] = la >= lb ? lo[j] : hi[j];
            res[2 * N + k] = up != up ? INFINITY : up;
            res[3 * N + k] = floor;
            res[4 * N + k] = va ? ua : INFINITY;
            res[5 * N + k] = vb ? ub : INFINITY;
            res[6 * N + k] = la;
            res[7 * N + k] = lb;
            res[8 * N + k] = fabs(pam);
            res[9 * N + k] = fabs(pbm);
            res[10 * N + k] = same;
        }
        if (settled)
            res[j] = all;
    }
    return done(views, got, &ov, 0);
}
"""
