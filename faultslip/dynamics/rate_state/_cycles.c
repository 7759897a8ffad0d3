/* A quasi-dynamic rate-and-state spring-block fault, integrated from one event edge to the next.
 *
 * The same scheme as faultslip.dynamics.rate_state.slider.dopri5 on the same states, compiled: Dormand &
 * Prince (1980) 5(4) with the PI step controller of Hairer & Wanner II, IV.2, on y = (x, psi, slip),
 * x = ln(V / V0), psi = ln(V0 theta / D_c), loaded at the constant plate rate V_pl:
 *
 *     V = V0 e^x,   psi' = (V0 e^-psi - V) / D_c (aging)  or  -(V / D_c)(x + psi) (slip),
 *     x' = (k (V_pl - V) - sigma_n b psi') / (sigma_n a + eta V),   slip' = V.
 *
 * run() steps from the state it is given until an accepted step ends on the other side of the event
 * threshold x_th (rising when outside an event, falling inside one), and locates the crossing within that
 * step as fault_cycles does in Python: 60 bisections on the scheme's continuous extension of order 4. Python keeps the bookkeeping (events,
 * settling, restarts); only the steps are here, which is where the time went (3.5 ms a cycle in Python,
 * about 0.1 ms here). Why C and not numba, which compiles the lab kernel: importing numba costs 0.4 s,
 * more than a hundred cycles take, and a cycle run is one short process.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

/* Dormand & Prince (1980) 5(4): Hairer, Norsett & Wanner, Solving ODEs I, Table 5.2 (as dormand_prince.py) */
#define C2 (1.0 / 5.0)
#define C3 (3.0 / 10.0)
#define C4 (4.0 / 5.0)
#define C5 (8.0 / 9.0)
#define A21 (1.0 / 5.0)
#define A31 (3.0 / 40.0)
#define A32 (9.0 / 40.0)
#define A41 (44.0 / 45.0)
#define A42 (-56.0 / 15.0)
#define A43 (32.0 / 9.0)
#define A51 (19372.0 / 6561.0)
#define A52 (-25360.0 / 2187.0)
#define A53 (64448.0 / 6561.0)
#define A54 (-212.0 / 729.0)
#define A61 (9017.0 / 3168.0)
#define A62 (-355.0 / 33.0)
#define A63 (46732.0 / 5247.0)
#define A64 (49.0 / 176.0)
#define A65 (-5103.0 / 18656.0)
#define B1 (35.0 / 384.0)
#define B3 (500.0 / 1113.0)
#define B4 (125.0 / 192.0)
#define B5 (-2187.0 / 6784.0)
#define B6 (11.0 / 84.0)
#define E1 (71.0 / 57600.0)
#define E3 (-71.0 / 16695.0)
#define E4 (71.0 / 1920.0)
#define E5 (-17253.0 / 339200.0)
#define E6 (22.0 / 525.0)
#define E7 (-1.0 / 40.0)

/* status codes, as faultslip.dynamics.rate_state.native reads them */
#define CROSSED 0
#define HORIZON 1
#define TOO_MANY_STEPS 2
#define STEP_COLLAPSE 3

typedef struct {
    int aging;
    double v0, dc, k, sigma_a, sigma_b, damping, plate_rate;
} Fault;

static void rates(const Fault *f, const double *y, double *dy)
{
    double speed = f->v0 * exp(y[0]);
    double dpsi = f->aging ? (f->v0 * exp(-y[1]) - speed) / f->dc : -(speed / f->dc) * (y[0] + y[1]);
    dy[0] = (f->k * (f->plate_rate - speed) - f->sigma_b * dpsi) / (f->sigma_a + f->damping * speed);
    dy[1] = dpsi;
    dy[2] = speed;
}

static double rms3(const double *v)
{
    return sqrt((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) / 3.0);
}

/* Dormand-Prince's continuous extension of order 4 (Shampine 1986), as dormand_prince.py's _P: the weight of
 * stage i at the step fraction u is the polynomial P_i1 u + P_i2 u^2 + P_i3 u^3 + P_i4 u^4 (k2's is zero) */
static const double P[6][4] = {
    {1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0, -12715105075.0 / 11282082432.0},
    {0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0, 87487479700.0 / 32700410799.0},
    {0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0, -10690763975.0 / 1880347072.0},
    {0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0, 701980252875.0 / 199316789632.0},
    {0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0, -1453857185.0 / 822651844.0},
    {0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0}};

static void continuous(const double *y0, double h, const double *const *k, double u, double *out)
{
    double w[6];
    for (int i = 0; i < 6; i++)
        w[i] = u * (P[i][0] + u * (P[i][1] + u * (P[i][2] + u * P[i][3])));
    for (int j = 0; j < 3; j++) {
        double sum = 0.0;
        for (int i = 0; i < 6; i++)
            sum += w[i] * k[i][j];
        out[j] = y0[j] + h * sum;
    }
}

/* the crossing of x = threshold inside the step of size h from y0 with stages k (k1, k3..k7), by bisection on
 * the continuous extension: accurate to the step's own error (a cubic Hermite of the ends errs by O(h^4)) */
static double locate(const double *y0, const double *y1, double h, const double *const *k, double threshold,
                     double *yc)
{
    double low = 0.0, high = 1.0, trial[3];
    int rising = y1[0] > y0[0];
    for (int n = 0; n < 60; n++) {
        double u = 0.5 * (low + high);
        continuous(y0, h, k, u, trial);
        if ((trial[0] > threshold) == rising)
            high = u;
        else
            low = u;
    }
    continuous(y0, h, k, high, yc);
    yc[0] = threshold;
    return high * h;
}

static PyObject *run(PyObject *self, PyObject *args)
{
    Fault f;
    double y[3], atol[3], h, t_end, rtol, threshold;
    int inside;
    long long max_steps;
    if (!PyArg_ParseTuple(args, "dddddddddpdddddddpdL", &y[0], &y[1], &y[2], &h, &t_end, &rtol, &atol[0],
                          &atol[1], &atol[2], &f.aging, &f.v0, &f.dc, &f.k, &f.sigma_a, &f.sigma_b, &f.damping,
                          &f.plate_rate, &inside, &threshold, &max_steps))
        return NULL;
    double k1[3], k2[3], k3[3], k4[3], k5[3], k6[3], k7[3], stage[3], y_new[3], yc[3] = {NAN, NAN, NAN};
    double t = 0.0, t_cross = NAN, peak = -INFINITY, previous_error = 1e-4;
    long long steps = 0, nfev = 1;
    int status = HORIZON;
    rates(&f, y, k1);
    if (!(t_end > 0.0))
        goto done;
    if (!(h > 0.0)) { /* Hairer, Norsett & Wanner I, II.4: a first step from the size of y, f and f' */
        double scaled[3], scales[3];
        for (int i = 0; i < 3; i++)
            scales[i] = atol[i] + rtol * fabs(y[i]);
        for (int i = 0; i < 3; i++)
            scaled[i] = y[i] / scales[i];
        double d0 = rms3(scaled);
        for (int i = 0; i < 3; i++)
            scaled[i] = k1[i] / scales[i];
        double d1 = rms3(scaled);
        double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
        if (h0 > t_end)
            h0 = t_end;
        for (int i = 0; i < 3; i++)
            stage[i] = y[i] + h0 * k1[i];
        rates(&f, stage, k2);
        nfev += 1;
        for (int i = 0; i < 3; i++)
            scaled[i] = (k2[i] - k1[i]) / scales[i];
        double d2 = rms3(scaled) / h0;
        if (!isfinite(d2))
            d2 = INFINITY;
        double big = d1 > d2 ? d1 : d2;
        double h1 = big > 1e-15 ? pow(0.01 / big, 0.2) : fmax(1e-6, h0 * 1e-3);
        h = fmin(fmin(100 * h0, h1), t_end);
        if (!(isfinite(h) && h > 0)) /* a state far beyond its scale: start small, the control adapts */
            h = 1e-6 * t_end;
    }
    if (h < 1e-300)
        h = 1e-300;
    double floor_h = 1e-14 * 1e-300;
    while (t < t_end) {
        if (steps >= max_steps) {
            status = TOO_MANY_STEPS;
            goto done;
        }
        double t_next = t + h;
        if (t_next >= t_end) { /* the last step lands on t_end exactly */
            h = t_end - t;
            t_next = t_end;
        }
        for (int i = 0; i < 3; i++)
            stage[i] = y[i] + h * A21 * k1[i];
        rates(&f, stage, k2);
        for (int i = 0; i < 3; i++)
            stage[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        rates(&f, stage, k3);
        for (int i = 0; i < 3; i++)
            stage[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        rates(&f, stage, k4);
        for (int i = 0; i < 3; i++)
            stage[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        rates(&f, stage, k5);
        for (int i = 0; i < 3; i++)
            stage[i] = y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        rates(&f, stage, k6);
        for (int i = 0; i < 3; i++)
            y_new[i] = y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i]);
        rates(&f, y_new, k7);
        nfev += 6;
        double error = 0.0;
        for (int i = 0; i < 3; i++) {
            double e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            double scale = atol[i] + rtol * fmax(fabs(y[i]), fabs(y_new[i]));
            error += (e / scale) * (e / scale);
        }
        error = sqrt(error / 3.0);
        if (!isfinite(error)) { /* a trial stage left the domain (exp overflow): a smaller step */
            h *= 0.1;
            if (h < floor_h) {
                status = STEP_COLLAPSE;
                goto done;
            }
            continue;
        }
        if (error <= 1.0) {
            double factor = error > 0 ? 0.9 * pow(error, -0.14) * pow(previous_error, 0.08) : 5.0;
            int crossed = (y_new[0] > threshold) != inside;
            if (crossed) {
                const double *stages[6] = {k1, k3, k4, k5, k6, k7};
                t_cross = t + locate(y, y_new, h, stages, threshold, yc);
            }
            else if (y_new[0] > peak) /* inside: the event's peak; outside: the highest speed below it */
                peak = y_new[0];
            t = t_next;
            for (int i = 0; i < 3; i++) {
                y[i] = y_new[i];
                k1[i] = k7[i];
            }
            steps += 1;
            h *= fmin(5.0, fmax(0.2, factor));
            previous_error = fmax(error, 1e-4);
            if (crossed) {
                status = CROSSED;
                goto done;
            }
        } else {
            h *= fmax(0.2, 0.9 * pow(error, -0.2));
        }
        floor_h = 4e-16 * fmax(fabs(t), 1e-300) * 16; /* a few float spacings of t */
        if (h < floor_h) {
            status = STEP_COLLAPSE;
            goto done;
        }
    }
done:
    return Py_BuildValue("iddddLLddddd", status, t, y[0], y[1], y[2], steps, nfev, h, t_cross, yc[1], yc[2], peak);
}

static PyMethodDef methods[] = {
    {"run", run, METH_VARARGS,
     "run(x, psi, slip, h, t_end, rtol, atol_x, atol_psi, atol_slip, aging, V0, D_c, k, sigma_a, sigma_b, eta, "
     "V_pl, inside, x_threshold, max_steps) -> (status, t, x, psi, slip, steps, evaluations, next h, "
     "crossing time, psi and slip at the crossing, peak x)"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_cycles",
                                    "A quasi-dynamic rate-and-state spring-block stepped from event edge to event edge.",
                                    -1, methods};

PyMODINIT_FUNC PyInit__cycles(void)
{
    return PyModule_Create(&module);
}
