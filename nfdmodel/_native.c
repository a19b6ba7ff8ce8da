/* nfdmodel._native: the Python binding of nfd_kernel.c (a plain CPython extension, no numpy
 * headers: arrays arrive through the buffer protocol as C-contiguous float64 / int64 memory).
 *
 * A step is two calls, so that Python allocates the trial history of exactly the contacts that
 * load (nfdmodel.native):
 *   unload(three_halves, delta, delta_res, K_u, delta_max, force, index[, exponent]) -> (k, finite)
 *       the unloading/reloading force of every contact, P = K_u <delta - delta_res>^n (n = 3/2 or 1,
 *       or each contact's exponent[i]: vz_unload), and the positions of the k contacts with
 *       delta > delta_max (written to index[0:k]);
 *   load(law, params, index, delta, a_e_max, force, delta_max', P_max', delta_res', K_u', a_e_max')
 *       -> (largest Newton count, beyond-window count, largest P_max, position of the largest
 *           contact radius, that radius, finite)
 *       the loading branch of those k contacts: force[index[i]] and the new history at i.
 *   hertz(delta, k, force) -> finite
 *   elastic_energy(law, delta, delta_res, exponent, force, energy) -> None: nfd_elastic_energy of n contacts
 *       (exponent: the history's a_e_max slot, the unloading exponent m of vz_unload, unused by the others)
 *   yield_factor(nu) -> A_Y(nu) of nfd_yield_factor (the caller checks 0 <= nu < NFD_NU_MAX)
 *   vz_admissible(Ca_hat, Kc_hat) -> (NFD_VZ_* code, P/P_Y, restitution) of nfd_vz_admissible
 *   contact_step(law, params, table, friction, update, dt, geometry, history, out) -> (status, at)
 *       nfd_contact_step (nfd_friction.h) of n contacts: geometry 16 doubles each (n[3], delta,
 *       R_i, R_j, v[3], omega_i[3], omega_j[3], m*), history 13 (nfd_history, then
 *       nfd_friction_history), out 28 (the new history 13, force 3, torque_i 3, torque_j 3, P,
 *       F_n, a, F_t 3); table: None, (x, f, g) (vz_table) or (x, f, g, x_unload, dent, exponent)
 *       (vz_unload); friction: the nfd_friction fields in order;
 *       status: the first negative law status (at: that contact) or 0.
 *   rate_step(base_law, params, table, rate, k, K, m_star, delta, velocity, delta_max, P_max, delta_res, K_u,
 *             a_e_max, rate_factor, strain_rate_per_speed, loading_work, force, index, delta_max', P_max',
 *             delta_res', K_u', a_e_max', rate_factor', strain_rate_per_speed', loading_work')
 *       -> (k, status, at, largest Newton count, beyond-window count, largest base P_max)
 *       nfd_rate_step (k = 0: R fixed at first contact) or nfd_rate_relaxing_step (k > 0: the relaxing form, K =
 *       k E* / sigma_Y; strain_rate_per_speed and loading_work read and written only then) (nfd_rate.h) of n
 *       contacts: the force of each, and the new history of the contacts whose turning point moved, that first
 *       touched or (relaxing) loaded (positions in index[0:k], values at 0..k-1); rate: (NFD_RATE_* code, first,
 *       second, c) of nfd_rate_init; status: the first negative one (at: that contact, nothing else written
 *       after it) or 0; a ValueError when nfd_rate_init or nfd_rate_relaxing refuses the constants.
 *   collide(..., [table, rate, rate_factor']): with rate, the rate-aware law on the base law `law` (table:
 *       None or its tables), R of each impact in rate_factor'.
 * finite: 0.0 when every force written is finite, else inf or NaN (what nfdmodel.history.check_force
 * needs: a value that is finite exactly when the forces are).
 * law: an NFD_LAW_* code of nfd_limits.h; params: (R*, E*, P_Y, delta_Y, a_Y, p_Y, k_H, Ca, Kc,
 * window P_max, K1, K2, c1, P_Y^(1/3)) [SI].
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>

#include "nfd_friction.h"
#include "nfd_rate.h"
#include "nfd_unload.h"

static int check_length(Py_buffer *buffer, Py_ssize_t count, Py_ssize_t itemsize, const char *name)
{
    if (buffer->len != count * itemsize) {
        PyErr_Format(PyExc_ValueError, "%s: expected %zd items of %zd bytes, got %zd bytes", name, count, itemsize,
                     buffer->len);
        return 0;
    }
    return 1;
}

static PyObject *native_unload(PyObject *self, PyObject *args)
{
    int three_halves;
    Py_buffer delta, delta_res, K_u, delta_max, force, index, exponent = {0};
    (void)self;
    if (!PyArg_ParseTuple(args, "py*y*y*y*w*w*|y*", &three_halves, &delta, &delta_res, &K_u, &delta_max, &force,
                          &index, &exponent))
        return NULL;
    const double *m = exponent.buf;
    Py_ssize_t n = delta.len / (Py_ssize_t)sizeof(double);
    Py_ssize_t k = 0;
    double sum = 0.0;
    if (check_length(&delta_res, n, 8, "delta_res") && check_length(&K_u, n, 8, "K_u") &&
        check_length(&delta_max, n, 8, "delta_max") && check_length(&force, n, 8, "force") &&
        check_length(&index, n, 8, "index") && (m == NULL || check_length(&exponent, n, 8, "exponent"))) {
        const double *d = delta.buf, *res = delta_res.buf, *K = K_u.buf, *dmax = delta_max.buf;
        double *f = force.buf;
        int64_t *idx = index.buf;
        int finite = 1;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n; ++i) {
            double gap = d[i] - res[i];
            if (gap < 0.0) gap = 0.0;
            double p;
            if (m) {
                p = K[i] * pow(gap, m[i]);
            } else if (three_halves) {
                p = sqrt(gap);
                p *= gap;
                p *= K[i];
            } else {
                p = gap * K[i];
            }
            f[i] = p;
            finite &= p - p == 0.0;
            idx[k] = i;                     /* branch-free: kept only when loading */
            k += d[i] > dmax[i];
        }
        sum = finite ? 0.0 : INFINITY;
        Py_END_ALLOW_THREADS
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&delta); PyBuffer_Release(&delta_res); PyBuffer_Release(&K_u);
    PyBuffer_Release(&delta_max); PyBuffer_Release(&force); PyBuffer_Release(&index);
    if (m) PyBuffer_Release(&exponent);
    if (failed) return NULL;
    return Py_BuildValue("nd", k, sum);
}

static int read_params(PyObject *tuple, nfd_params *p)
{
    double v[14];
    if (!PyArg_ParseTuple(tuple, "dddddddddddddd", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8],
                          &v[9], &v[10], &v[11], &v[12], &v[13]))
        return 0;
    p->R_star = v[0]; p->E_star = v[1]; p->P_Y = v[2]; p->delta_Y = v[3]; p->a_Y = v[4]; p->p_Y = v[5];
    p->hertz_k = v[6]; p->Ca = v[7]; p->Kc = v[8]; p->window_P_max = v[9]; p->K1 = v[10]; p->K2 = v[11];
    p->c1 = v[12]; p->u_Y = v[13];
    return 1;
}

static PyObject *native_load(PyObject *self, PyObject *args)
{
    int law;
    PyObject *params_tuple;
    Py_buffer index, delta, a_e_max, force, o_dmax, o_P, o_res, o_K, o_ae;
    nfd_params p;
    (void)self;
    if (!PyArg_ParseTuple(args, "iOy*y*y*w*w*w*w*w*w*", &law, &params_tuple, &index, &delta, &a_e_max, &force,
                          &o_dmax, &o_P, &o_res, &o_K, &o_ae))
        return NULL;
    Py_ssize_t k = index.len / 8, n = delta.len / 8;
    int max_iterations = 0;
    Py_ssize_t beyond = 0, widest = -1, bad = -1;
    double largest_P = 0.0, widest_radius = -1.0, sum = 0.0;
    if (read_params(params_tuple, &p) && check_length(&a_e_max, n, 8, "a_e_max") && check_length(&force, n, 8, "force") &&
        check_length(&o_dmax, k, 8, "delta_max") && check_length(&o_P, k, 8, "P_max") &&
        check_length(&o_res, k, 8, "delta_res") && check_length(&o_K, k, 8, "K_u") && check_length(&o_ae, k, 8, "a_e_max")) {
        const int64_t *idx = index.buf;
        const double *d = delta.buf, *ae = a_e_max.buf;
        double *f = force.buf, *dm = o_dmax.buf, *P = o_P.buf, *res = o_res.buf, *K = o_K.buf, *aeo = o_ae.buf;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < k; ++i)
            if (idx[i] < 0 || idx[i] >= n) { bad = i; break; }
        if (bad < 0 && law == NFD_LAW_VZ) {
            /* vz: gather, the batch solve (vectorised fast path), scatter the forces */
            for (Py_ssize_t i = 0; i < k; ++i) {
                dm[i] = d[idx[i]];
                aeo[i] = ae[idx[i]];
            }
            max_iterations = nfd_vz_load((size_t)k, &p, dm, aeo, P, res, K);
            int finite = 1;
            for (Py_ssize_t i = 0; i < k; ++i) {
                double P_i = P[i];
                f[idx[i]] = P_i;
                finite &= P_i - P_i == 0.0;
                beyond += P_i > p.window_P_max;
                largest_P = P_i > largest_P ? P_i : largest_P;
                double excess = P_i - p.P_Y;
                double radius = aeo[i] + p.Ca * (excess > 0.0 ? excess : 0.0);
                if (radius > widest_radius || widest < 0) { widest_radius = radius; widest = i; }
            }
            sum = finite ? 0.0 : INFINITY;
        } else if (bad < 0) {
            for (Py_ssize_t i = 0; i < k; ++i) {
                int64_t j = idx[i];
                nfd_history h = {0.0, 0.0, 0.0, 0.0, ae[j]};
                h.delta_max = -INFINITY;                     /* the caller selected loading contacts */
                nfd_history out;
                double force_j = 0.0;
                nfd_step(law, d[j], &p, NULL, &h, &force_j, &out, NULL);
                f[j] = force_j;
                sum += force_j;
                dm[i] = out.delta_max; P[i] = out.P_max; res[i] = out.delta_res; K[i] = out.K_u; aeo[i] = out.a_e_max;
            }
        }
        Py_END_ALLOW_THREADS
        if (bad >= 0) PyErr_Format(PyExc_ValueError, "index[%zd] out of range 0..%zd", bad, n - 1);
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&index); PyBuffer_Release(&delta); PyBuffer_Release(&a_e_max); PyBuffer_Release(&force);
    PyBuffer_Release(&o_dmax); PyBuffer_Release(&o_P); PyBuffer_Release(&o_res); PyBuffer_Release(&o_K);
    PyBuffer_Release(&o_ae);
    if (failed) return NULL;
    return Py_BuildValue("indndd", max_iterations, beyond, largest_P, widest, widest_radius, sum);
}

/* *t from a tuple (x, f, g) (vz_table) or (x, f, g, x_unload, dent, exponent) (vz_unload); 0 with a
 * ValueError set when the nodes break nfd_table_init's or nfd_unload_table_init's rules. */
static int read_table(PyObject *tuple, nfd_table *t)
{
    Py_buffer b[6] = {{0}};
    if (!PyArg_ParseTuple(tuple, "y*y*y*|y*y*y*", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5])) return 0;
    Py_ssize_t nodes = b[0].len / 8, unload_nodes = b[3].len / 8;
    int ok = nodes <= NFD_TABLE_MAX_NODES && b[1].len == b[0].len && b[2].len == b[0].len &&
             nfd_table_init(t, (int)nodes, b[0].buf, b[1].buf, b[2].buf) == 0;
    if (!ok)
        PyErr_Format(PyExc_ValueError, "table out of range: 2..%d nodes with x[0] = 1, f[0] = 0, g[0] = 1, x "
                     "increasing, f non-decreasing, g > 0", NFD_TABLE_MAX_NODES);
    if (ok && b[3].buf) {
        ok = unload_nodes <= NFD_TABLE_MAX_NODES && b[4].len == b[3].len && b[5].len == b[3].len &&
             nfd_unload_table_init(t, (int)unload_nodes, b[3].buf, b[4].buf, b[5].buf) == 0;
        if (!ok)
            PyErr_Format(PyExc_ValueError, "unloading table out of range: 2..%d nodes with x_unload[0] = 1, dent[0] "
                         "= 0, exponent[0] = 1.5, x_unload increasing, 0 <= dent < 1, exponent > 0",
                         NFD_TABLE_MAX_NODES);
    }
    for (int k = 0; k < 6; ++k)
        if (b[k].buf) PyBuffer_Release(&b[k]);
    return ok;
}

/* load_table(params, table, index, delta, P_max_history, force, delta_max', P_max', delta_res', K_u', a_e_max')
 * -> as load: the loading branch of the selected contacts (start: the history's P_max) of the
 * vz_table law, table (x, f, g), or of the vz_unload law, table (x, f, g, x_unload, dent,
 * exponent), whose a_e_max' is the unloading exponent m. A ValueError when the table breaks the
 * rules of nfd_table_init or nfd_unload_table_init. */
static PyObject *native_load_table(PyObject *self, PyObject *args)
{
    PyObject *params_tuple, *table_tuple;
    Py_buffer index, delta, P_hist, force, o_dmax, o_P, o_res, o_K, o_ae;
    nfd_params p;
    nfd_table table;
    (void)self;
    if (!PyArg_ParseTuple(args, "OOy*y*y*w*w*w*w*w*w*", &params_tuple, &table_tuple, &index, &delta, &P_hist,
                          &force, &o_dmax, &o_P, &o_res, &o_K, &o_ae))
        return NULL;
    Py_ssize_t k = index.len / 8, n = delta.len / 8;
    int max_iterations = 0, finite = 1;
    Py_ssize_t beyond = 0, widest = -1, bad = -1;
    double largest_P = 0.0, widest_radius = -1.0;
    if (read_params(params_tuple, &p) && read_table(table_tuple, &table) &&
        check_length(&P_hist, n, 8, "P_max") && check_length(&force, n, 8, "force") &&
        check_length(&o_dmax, k, 8, "delta_max") && check_length(&o_P, k, 8, "P_max'") &&
        check_length(&o_res, k, 8, "delta_res") && check_length(&o_K, k, 8, "K_u") && check_length(&o_ae, k, 8, "a_e_max")) {
        const int64_t *idx = index.buf;
        const double *d = delta.buf, *Ph = P_hist.buf;
        double *f = force.buf, *dm = o_dmax.buf, *P = o_P.buf, *res = o_res.buf, *K = o_K.buf, *aeo = o_ae.buf;
        const int law = table.n_unload > 0 ? NFD_LAW_VZ_UNLOAD : NFD_LAW_VZ_TABLE;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < k; ++i) {
            int64_t j = idx[i];
            if (j < 0 || j >= n) { bad = i; break; }
            nfd_history h = {-INFINITY, Ph[j], 0.0, 0.0, 0.0}, out;   /* the caller selected loading contacts */
            double force_j = 0.0;
            int iterations = 0;
            nfd_step(law, d[j], &p, &table, &h, &force_j, &out, &iterations);
            if (iterations > max_iterations) max_iterations = iterations;
            f[j] = force_j;
            finite &= force_j - force_j == 0.0;
            dm[i] = out.delta_max; P[i] = out.P_max; res[i] = out.delta_res; K[i] = out.K_u; aeo[i] = out.a_e_max;
            beyond += out.P_max > p.window_P_max;
            largest_P = out.P_max > largest_P ? out.P_max : largest_P;
            double radius = out.P_max > p.P_Y ? nfd_vz_table_radius(&p, &table, out.P_max)
                                              : sqrt(p.R_star * (out.delta_max > 0.0 ? out.delta_max : 0.0));
            if (radius > widest_radius || widest < 0) { widest_radius = radius; widest = i; }
        }
        Py_END_ALLOW_THREADS
        if (bad >= 0) PyErr_Format(PyExc_ValueError, "index[%zd] out of range 0..%zd", bad, n - 1);
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&index); PyBuffer_Release(&delta); PyBuffer_Release(&P_hist); PyBuffer_Release(&force);
    PyBuffer_Release(&o_dmax); PyBuffer_Release(&o_P); PyBuffer_Release(&o_res); PyBuffer_Release(&o_K);
    PyBuffer_Release(&o_ae);
    if (failed) return NULL;
    return Py_BuildValue("indndd", max_iterations, beyond, largest_P, widest, widest_radius, finite ? 0.0 : INFINITY);
}

/* *r from (rate law code, first, second, c) and the base law code; 0 with a ValueError set when refused. */
static int read_rate(PyObject *tuple, int base_law, nfd_rate *r)
{
    int rate_law;
    double first, second, c;
    if (!PyArg_ParseTuple(tuple, "iddd", &rate_law, &first, &second, &c)) return 0;
    if (nfd_rate_init(r, base_law, rate_law, first, second, c) != 0) {
        PyErr_Format(PyExc_ValueError, "rate out of range: base law vz or vz_table, Johnson-Cook C >= 0 and "
                     "eps_dot_0 > 0, or Cowper-Symonds D > 0 and q > 0, and c > 0 (finite), got law %d, "
                     "rate law %d, %g, %g, c %g", base_law, rate_law, first, second, c);
        return 0;
    }
    return 1;
}

/* The rate-aware law's constants of a binding call (p, its tables, rate) and the lengths of its `count` input and
 * output buffers (8 bytes each, n of them); 0 with a Python error set when one is refused. */
static int read_rate_call(PyObject *params_tuple, PyObject *table_object, PyObject *rate_tuple, int base_law,
                          nfd_params *p, nfd_table *table, nfd_rate *rate, Py_buffer *in, Py_buffer *out, int count,
                          const char **names, const char **outputs)
{
    Py_ssize_t n = in[0].len / 8;
    int ok = read_params(params_tuple, p);
    if (ok && table_object != Py_None) ok = read_table(table_object, table);
    ok = ok && read_rate(rate_tuple, base_law, rate);
    for (int j = 0; ok && j < count; ++j)
        ok = check_length(&in[j], n, 8, names[j]) && check_length(&out[j], n, 8, outputs[j]);
    return ok;
}

static PyObject *native_rate_step(PyObject *self, PyObject *args)
{
    int base_law;
    double m_star, k_element, stiffness;
    PyObject *params_tuple, *table_object, *rate_tuple;
    Py_buffer in[10], out[10];
    nfd_params p;
    nfd_table table;
    nfd_rate rate;
    (void)self;
    if (!PyArg_ParseTuple(args, "iOOOdddy*y*y*y*y*y*y*y*y*y*w*w*w*w*w*w*w*w*w*w*", &base_law, &params_tuple,
                          &table_object, &rate_tuple, &k_element, &stiffness, &m_star, &in[0], &in[1], &in[2],
                          &in[3], &in[4], &in[5], &in[6], &in[7], &in[8], &in[9], &out[0], &out[1], &out[2], &out[3],
                          &out[4], &out[5], &out[6], &out[7], &out[8], &out[9]))
        return NULL;
    static const char *names[10] = {"delta", "velocity", "delta_max", "P_max", "delta_res", "K_u", "a_e_max",
                                    "rate_factor", "strain_rate_per_speed", "loading_work"};
    static const char *outputs[10] = {"force", "index", "delta_max'", "P_max'", "delta_res'", "K_u'", "a_e_max'",
                                      "rate_factor'", "strain_rate_per_speed'", "loading_work'"};
    Py_ssize_t n = in[0].len / 8, k = 0, at = -1, beyond = 0;
    int status = NFD_OK, most = 0;
    int ok = read_rate_call(params_tuple, table_object, rate_tuple, base_law, &p, &table, &rate, in, out, 10, names,
                            outputs);
    double largest_P = 0.0;
    const int relaxing = k_element != 0.0;          /* k = 0: R fixed at first contact (nfd_rate_step) */
    if (ok && relaxing && (nfd_rate_relaxing(&rate, k_element) != 0 || !(stiffness > 0.0 && isfinite(stiffness)))) {
        PyErr_Format(PyExc_ValueError, "k out of range: need 0 < k and 0 < k E* / sigma_Y finite, got k %g, %g",
                     k_element, stiffness);
        ok = 0;
    }
    if (ok) {
        const double *d = in[0].buf, *v = in[1].buf, *dm = in[2].buf, *Pm = in[3].buf, *dr = in[4].buf,
                     *Ku = in[5].buf, *ae = in[6].buf, *Rf = in[7].buf, *rs = in[8].buf, *W = in[9].buf;
        double *f = out[0].buf, *o_dm = out[2].buf, *o_P = out[3].buf, *o_dr = out[4].buf, *o_K = out[5].buf,
               *o_ae = out[6].buf, *o_R = out[7].buf, *o_rs = out[8].buf, *o_W = out[9].buf;
        int64_t *idx = out[1].buf;
        const nfd_table *t = table_object != Py_None ? &table : NULL;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n; ++i) {
            nfd_history h = {dm[i], Pm[i], dr[i], Ku[i], ae[i]}, next;
            double R = Rf[i], per_speed = rs[i], work = W[i], force = 0.0;
            int iterations = 0;
            int code = relaxing ? nfd_rate_relaxing_step(&rate, d[i], v[i], m_star, stiffness, &p, t, &h, &R,
                                                         &per_speed, &work, &force, &next, &iterations)
                                : nfd_rate_step(&rate, d[i], v[i], m_star, &p, t, &h, &R, &force, &next, &iterations);
            if (code < 0) { status = code; at = i; break; }
            f[i] = force;
            most = iterations > most ? iterations : most;
            double square = pow(R > 0.0 ? R : 1.0, 2.0);
            int moved = d[i] / square > h.delta_max / square;
            int loading = relaxing && d[i] > h.delta_max && d[i] > 0.0;
            if (!moved && !loading && R == Rf[i]) continue;                 /* unchanged */
            if (moved) {
                double base_P = next.P_max / pow(R > 0.0 ? R : 1.0, 3.0);
                beyond += base_P > p.window_P_max;
                largest_P = base_P > largest_P ? base_P : largest_P;
            }
            idx[k] = i;
            o_dm[k] = next.delta_max; o_P[k] = next.P_max; o_dr[k] = next.delta_res; o_K[k] = next.K_u;
            o_ae[k] = next.a_e_max; o_R[k] = R; o_rs[k] = per_speed; o_W[k] = work;
            ++k;
        }
        Py_END_ALLOW_THREADS
    }
    int failed = PyErr_Occurred() != NULL;
    for (int j = 0; j < 10; ++j) { PyBuffer_Release(&in[j]); PyBuffer_Release(&out[j]); }
    if (failed) return NULL;
    return Py_BuildValue("ninind", k, status, at, most, beyond, largest_P);
}

static PyObject *native_hertz(PyObject *self, PyObject *args)
{
    Py_buffer delta, force;
    double k, sum = 0.0;
    (void)self;
    if (!PyArg_ParseTuple(args, "y*dw*", &delta, &k, &force)) return NULL;
    Py_ssize_t n = delta.len / 8;
    if (check_length(&force, n, 8, "force")) {
        const double *d = delta.buf;
        double *f = force.buf;
        int finite = 1;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n; ++i) {
            double x = d[i] > 0.0 ? d[i] : 0.0;
            double p = sqrt(x);
            p *= x;
            p *= k;
            f[i] = p;
            finite &= p - p == 0.0;
        }
        sum = finite ? 0.0 : INFINITY;
        Py_END_ALLOW_THREADS
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&delta); PyBuffer_Release(&force);
    if (failed) return NULL;
    return PyFloat_FromDouble(sum);
}

static PyObject *native_elastic_energy(PyObject *self, PyObject *args)
{
    Py_buffer delta, delta_res, exponent, force, energy;
    int law;
    (void)self;
    if (!PyArg_ParseTuple(args, "iy*y*y*y*w*", &law, &delta, &delta_res, &exponent, &force, &energy)) return NULL;
    Py_ssize_t n = delta.len / 8;
    if (check_length(&delta_res, n, 8, "delta_res") && check_length(&exponent, n, 8, "exponent") &&
        check_length(&force, n, 8, "force") && check_length(&energy, n, 8, "energy")) {
        const double *d = delta.buf, *r = delta_res.buf, *m = exponent.buf, *f = force.buf;
        double *out = energy.buf;
        for (Py_ssize_t i = 0; i < n; ++i) {
            nfd_history h = {0.0, 0.0, r[i], 0.0, m[i]};
            out[i] = nfd_elastic_energy(law, d[i], &h, f[i]);
        }
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&delta); PyBuffer_Release(&delta_res); PyBuffer_Release(&exponent); PyBuffer_Release(&force);
    PyBuffer_Release(&energy);
    if (failed) return NULL;
    Py_RETURN_NONE;
}

/* One sphere-on-flat impact per velocity, leap-frog (nfdmodel.collision._time_loop, the same
 * operations per step): the velocities are independent, so each runs its own loop until it
 * separates; the sweep's step count is the largest. */
static PyObject *native_collide(PyObject *self, PyObject *args)
{
    int law;
    PyObject *params_tuple;
    Py_buffer v_in, v_out, contact_time, loading_area, unloading_area, P_max_out, delta_max_out, delta_res_out;
    double dt, mass;
    long long max_steps;
    nfd_params p;
    (void)self;
    PyObject *table_object = Py_None, *rate_tuple = Py_None;
    Py_buffer rate_out = {0};
    nfd_table table;
    nfd_rate rate;
    if (!PyArg_ParseTuple(args, "iOy*ddLw*w*w*w*w*w*w*|OOw*", &law, &params_tuple, &v_in, &dt, &mass, &max_steps, &v_out,
                          &contact_time, &loading_area, &unloading_area, &P_max_out, &delta_max_out, &delta_res_out,
                          &table_object, &rate_tuple, &rate_out))
        return NULL;
    Py_ssize_t n = v_in.len / 8;
    long long steps = 0;
    int max_iterations = 0, status = NFD_OK;
    Py_ssize_t failed_at = -1;
    double failed_delta = 0.0;
    int ok = read_params(params_tuple, &p);
    if (ok && table_object != Py_None) ok = read_table(table_object, &table);
    if (ok && rate_tuple != Py_None) ok = read_rate(rate_tuple, law, &rate) && check_length(&rate_out, n, 8, "rate_factor");
    if (ok) {
        const double *v0 = v_in.buf;
        const nfd_table *t = table_object != Py_None ? &table : NULL;
        double *R_out = rate_tuple != Py_None ? rate_out.buf : NULL;
        double *vo = v_out.buf, *ct = contact_time.buf, *la = loading_area.buf, *ua = unloading_area.buf;
        double *pm = P_max_out.buf, *dm = delta_max_out.buf, *dr = delta_res_out.buf;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n && status >= 0; ++i) {
            nfd_history h = {0.0, 0.0, 0.0, 0.0, 0.0}, next;
            double delta = 0.0, force = 0.0, velocity = v0[i], loading = 0.0, unloading = 0.0, R = 0.0;
            double peak = 0.0, deepest = 0.0, time_out = 0.0, v_sep = 0.0;
            long long step = 0;
            for (;;) {
                if (step >= max_steps) { status = -10; failed_at = i; break; }
                velocity = velocity - force * (dt / mass);
                double delta_new = delta + velocity * dt;
                double force_new = 0.0;
                int iterations = 0;
                int code = R_out ? nfd_rate_step(&rate, delta_new, velocity, mass, &p, t, &h, &R, &force_new, &next,
                                                 &iterations)
                                 : nfd_step(law, delta_new, &p, t, &h, &force_new, &next, &iterations);
                if (code < 0) { status = code; failed_at = i; failed_delta = delta_new; break; }
                h = next;
                if (iterations > max_iterations) max_iterations = iterations;
                double increment = delta_new - delta;
                double area = 0.5 * (force + force_new) * increment;
                int separating = force_new == 0.0 && velocity < 0.0;
                if (separating) {
                    double residual = law == NFD_LAW_HERTZ ? 0.0 : h.delta_res;
                    double fraction = (delta - residual) / (increment < 0 ? -increment : 1.0);
                    fraction = fraction < 0.0 ? 0.0 : (fraction > 1.0 ? 1.0 : fraction);
                    area = 0.5 * force * fraction * increment;
                    time_out = ((double)step + fraction) * dt;
                    v_sep = velocity;
                }
                if (increment > 0) loading += area;
                if (increment < 0) unloading += -area;
                if (force_new > peak) peak = force_new;
                if (delta_new > deepest) deepest = delta_new;
                delta = delta_new;
                force = force_new;
                ++step;
                if (separating) break;
            }
            if (step > steps) steps = step;
            vo[i] = v_sep; ct[i] = time_out; la[i] = loading; ua[i] = unloading;
            pm[i] = peak; dm[i] = deepest; dr[i] = law == NFD_LAW_HERTZ ? 0.0 : h.delta_res;
            if (R_out) R_out[i] = R;
        }
        Py_END_ALLOW_THREADS
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&v_in); PyBuffer_Release(&v_out); PyBuffer_Release(&contact_time);
    PyBuffer_Release(&loading_area); PyBuffer_Release(&unloading_area); PyBuffer_Release(&P_max_out);
    PyBuffer_Release(&delta_max_out); PyBuffer_Release(&delta_res_out);
    if (rate_out.buf) PyBuffer_Release(&rate_out);
    if (failed) return NULL;
    return Py_BuildValue("Liind", steps, max_iterations, status, failed_at, failed_delta);
}

static PyObject *native_yield_factor(PyObject *self, PyObject *args)
{
    double nu;
    (void)self;
    if (!PyArg_ParseTuple(args, "d", &nu)) return NULL;
    return PyFloat_FromDouble(nfd_yield_factor(nu));
}

static PyObject *native_vz_admissible(PyObject *self, PyObject *args)
{
    double Ca_hat, Kc_hat, load, restitution;
    (void)self;
    if (!PyArg_ParseTuple(args, "dd", &Ca_hat, &Kc_hat)) return NULL;
    int code = nfd_vz_admissible(Ca_hat, Kc_hat, &load, &restitution);
    return Py_BuildValue("idd", code, load, restitution);
}

static PyObject *native_contact_step(PyObject *self, PyObject *args)
{
    int law, update;
    double dt;
    PyObject *params_tuple, *table_object, *friction_tuple;
    Py_buffer geometry, history, out;
    nfd_params p;
    nfd_table table;
    nfd_friction f;
    (void)self;
    if (!PyArg_ParseTuple(args, "iOOOpdy*y*w*", &law, &params_tuple, &table_object, &friction_tuple, &update, &dt,
                          &geometry, &history, &out))
        return NULL;
    Py_ssize_t n = geometry.len / (16 * 8), at = -1;
    int status = NFD_OK, ok = read_params(params_tuple, &p);
    ok = ok && PyArg_ParseTuple(friction_tuple, "ididddidddiddd", &f.damping, &f.damping_coeff, &f.tangential,
                                &f.k_t, &f.x_gamma_t, &f.mu, &f.rolling, &f.k_roll, &f.gamma_roll, &f.mu_roll,
                                &f.twisting, &f.k_twist, &f.gamma_twist, &f.mu_twist);
    if (ok && table_object != Py_None) ok = read_table(table_object, &table);
    if (ok && check_length(&history, 13 * n, 8, "history") && check_length(&out, 28 * n, 8, "out")) {
        const double *g = geometry.buf, *hv = history.buf;
        double *o = out.buf;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n; ++i, g += 16, hv += 13, o += 28) {
            nfd_contact c = {{g[0], g[1], g[2]}, g[3], g[4], g[5], {g[6], g[7], g[8]}, {g[9], g[10], g[11]},
                             {g[12], g[13], g[14]}, g[15], dt};
            nfd_history h = {hv[0], hv[1], hv[2], hv[3], hv[4]}, h_out;
            nfd_friction_history fh = {{hv[5], hv[6], hv[7]}, {hv[8], hv[9], hv[10]}, hv[11], hv[12]}, fh_out;
            nfd_contact_result r;
            int code = nfd_contact_step(law, &c, &p, table_object != Py_None ? &table : NULL, &f, &h, &fh, update,
                                        &h_out, &fh_out, &r);
            if (code < 0) { status = code; at = i; break; }
            double values[28] = {h_out.delta_max, h_out.P_max, h_out.delta_res, h_out.K_u, h_out.a_e_max,
                                 fh_out.xi_t[0], fh_out.xi_t[1], fh_out.xi_t[2], fh_out.xi_roll[0], fh_out.xi_roll[1],
                                 fh_out.xi_roll[2], fh_out.theta_twist, fh_out.a_previous, r.force[0], r.force[1],
                                 r.force[2],
                                 r.torque_i[0], r.torque_i[1], r.torque_i[2], r.torque_j[0], r.torque_j[1],
                                 r.torque_j[2], r.P, r.F_n, r.a, r.F_t[0], r.F_t[1], r.F_t[2]};
            for (int k = 0; k < 28; ++k) o[k] = values[k];
        }
        Py_END_ALLOW_THREADS
    }
    int failed = PyErr_Occurred() != NULL;
    PyBuffer_Release(&geometry); PyBuffer_Release(&history); PyBuffer_Release(&out);
    if (failed) return NULL;
    return Py_BuildValue("in", status, at);
}

static PyMethodDef methods[] = {
    {"collide", native_collide, METH_VARARGS, "sphere-on-flat impacts, one loop per velocity"},
    {"unload", native_unload, METH_VARARGS, "unloading/reloading forces and the loading contacts"},
    {"load", native_load, METH_VARARGS, "the loading branch of the selected contacts"},
    {"load_table", native_load_table, METH_VARARGS, "the vz_table or vz_unload loading of the selected contacts"},
    {"rate_step", native_rate_step, METH_VARARGS,
     "nfd_rate_step or nfd_rate_relaxing_step of n contacts (nfd_rate.h)"},
    {"hertz", native_hertz, METH_VARARGS, "Hertz forces"},
    {"elastic_energy", native_elastic_energy, METH_VARARGS, "nfd_elastic_energy of n contacts"},
    {"yield_factor", native_yield_factor, METH_VARARGS, "A_Y(nu) of nfd_kernel.c (nfd_yield_factor)"},
    {"contact_step", native_contact_step, METH_VARARGS, "nfd_contact_step of n contacts (nfd_friction.h)"},
    {"vz_admissible", native_vz_admissible, METH_VARARGS, "(code, P/P_Y, e) of nfd_vz_admissible(Ca_hat, Kc_hat)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_native", "nfd_kernel.c bound to Python", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__native(void) { return PyModule_Create(&module); }
