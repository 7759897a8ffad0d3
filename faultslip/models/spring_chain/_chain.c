/* The spring-block chain, event by event, compiled: the scheme of faultslip.models.spring_chain.dynamics
 * (read its module docstring first), stepped in C.
 *
 * Sticks are analytic: every held block's force grows at k_p V, so the least headroom fails first. A slip
 * sub-phase, with the slipping set S fixed, is linear with constant coefficients, so each mode of S is a
 * damped oscillator in closed form. S falls into runs of neighbouring blocks that do not feel each other
 * (the held blocks between them are fixed), and a run of L blocks has modes in closed form too: its
 * stiffness is k_p + k_c T, T the path's Laplacian with a 1 added at an end held by a neighbour (a fixed
 * end) and nothing at the chain's end (a free one), whose eigenpairs are those of the discrete sine and
 * cosine transforms (Strang 1999, "The discrete cosine transform", SIAM Review 41, Table 1):
 *
 *     lambda_j = k_p + 4 k_c sin^2(theta_j / 2),
 *     fixed-fixed:  theta_j = (j + 1) pi / (L + 1),     phi_ij = sin((i + 1) theta_j)
 *     free-fixed:   theta_j = (2 j + 1) pi / (2 L + 1),  phi_ij = cos((i + 1/2) theta_j)
 *     free-free:    theta_j = j pi / L,                  phi_ij = cos((i + 1/2) theta_j)
 *
 * (fixed-free is free-fixed mirrored), each column normalised. So no eigensolver is needed: Python's
 * scipy.linalg.eigh_tridiagonal gives the same modes to round-off.
 *
 * A sub-phase ends at the first change: a slipping block's speed reaching zero, or a held neighbour's
 * |F| its limit, or a far held block's (one feeling only the plate) limit, whose time is linear. The
 * changes are bracketed on a grid of SAMPLES points a period of the fastest mode (the grid Python uses,
 * stopped at the first point where anything changes rather than at the end of a window) and located by
 * Brent's method (Brent 1973, "Algorithms for minimization without derivatives", ch. 4) on the closed
 * form to 1e-13 of the step. Python keeps the checks on its inputs and the catalogue's use; the loop of
 * events and sub-phases is here, where the time went (0.4 ms a sub-phase in Python, 377,000 sub-phases for
 * 100 blocks and 10,000 events).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SAMPLES 32        /* grid points a period of the fastest mode (dynamics.SAMPLES_PER_PERIOD) */
#define TOGETHER 1e-10    /* relative tolerance within which blocks stop or fail together (dynamics.TOGETHER) */
#define STEADY_PERIODS 200.0
#define HORIZON_PERIODS 200.0
#define PEAK_SAMPLES 16
#define EPS 2.220446049250313e-16

/* status codes, as faultslip.models.spring_chain.dynamics reads them */
#define DONE 0
#define BUDGET 1
#define STEADY 2
#define NO_CHANGE 3
#define OVERFLOW 4   /* the state's bounds left double precision: nothing after it can be trusted */

typedef struct {
    int n;
    double m, kp, kc, load, speed, mu_k, dashpot, gamma;
    const double *limit;
    /* the slipping set S: count blocks (sorted), in runs of neighbours */
    int count, runs;
    int *index, *position_in_s, *row_run, *run_start, *run_length, *run_offset;
    double *vectors;                           /* each run's L x L modes, row-major, at run_offset[r] */
    double *omega_d, *p0, *p1, *c, *d, *q, *dq;  /* one a mode (count) */
    double *xs, *vs;                           /* slipping blocks' positions and speeds (count) */
    double t0;
    /* held blocks next to S (near) and the rest (far) */
    int near_count, far_count;
    int *near_index, *near_moving, *near_moving_count, *far_index;
    double *near_fixed, *far_wait;
    /* work */
    double *x, *v, *force, *direction, *x_before;
    char *slipping_mask, *slipped, *stop_flag, *join_flag;
    int *candidate_kind, *candidate_row;
    double *candidate_root, *candidate_low, *candidate_high;
    double *curvature, *previous;              /* a bound on each speed's second derivative; its last grid value */
    double *acceleration;                      /* a bound on each slipping block's |x''| (count) */
    double *room_curvature, *room_previous, *room_now;  /* near blocks' headroom: |F''| bound, last and this point */
} Chain;

static void forces(const Chain *ch, const double *x, const double *v, double t, double *out)
{
    int n = ch->n;
    for (int i = 0; i < n; i++) {
        double coupling = 0.0;
        if (i + 1 < n)
            coupling += x[i + 1] - x[i];
        if (i > 0)
            coupling -= x[i] - x[i - 1];
        out[i] = ch->kp * (ch->speed * t - x[i]) + ch->dashpot * (ch->speed - v[i]) + ch->kc * coupling;
    }
}

/* the modes of S at the sub-phase's start t0 (positions x, speeds v) */
static void build_modes(Chain *ch, double t0)
{
    int n = ch->n, count = ch->count, offset = 0;
    const double *x = ch->x, *v = ch->v;
    double m = ch->m, kp = ch->kp, kc = ch->kc, speed = ch->speed, gamma = ch->gamma;
    ch->t0 = t0;
    ch->runs = 0;
    for (int s = 0; s < count; s++) {
        if (s == 0 || ch->index[s] != ch->index[s - 1] + 1) {
            ch->run_start[ch->runs] = s;
            ch->run_length[ch->runs] = 0;
            ch->runs++;
        }
        ch->run_length[ch->runs - 1]++;
        ch->row_run[s] = ch->runs - 1;
    }
    for (int r = 0; r < ch->runs; r++) {
        int start = ch->run_start[r], length = ch->run_length[r];
        int first = ch->index[start], last = ch->index[start + length - 1];
        int free_left = first == 0, free_right = last == n - 1;
        double *phi = ch->vectors + offset;
        ch->run_offset[r] = offset;
        offset += length * length;
        for (int j = 0; j < length; j++) {
            double theta, norm = 0.0;
            if (!free_left && !free_right)
                theta = (j + 1) * M_PI / (length + 1);
            else if (free_left && free_right)
                theta = j * M_PI / length;
            else
                theta = (2 * j + 1) * M_PI / (2 * length + 1);
            for (int i = 0; i < length; i++) {
                double value;
                if (!free_left && !free_right)
                    value = sin((i + 1) * theta);
                else if (free_left)  /* free-free or free-fixed: cosines from the free end */
                    value = cos((i + 0.5) * theta);
                else                 /* fixed-free: mirrored */
                    value = cos((length - 1 - i + 0.5) * theta);
                phi[i * length + j] = value;
                norm += value * value;
            }
            norm = 1.0 / sqrt(norm);
            for (int i = 0; i < length; i++)
                phi[i * length + j] *= norm;
            double half = sin(0.5 * theta);
            double omega2 = (kp + 4.0 * kc * half * half) / m;
            int mode = start + j;
            ch->omega_d[mode] = sqrt(omega2 - gamma * gamma);
            /* the forcing: constant (plate, dashpot, kinetic friction, held neighbours) and k_p V tau */
            double alpha = 0.0, beta = 0.0, q0 = 0.0, dq0 = 0.0;
            for (int i = 0; i < length; i++) {
                int block = ch->index[start + i];
                double pull = 0.0;
                if (block > 0 && !ch->slipping_mask[block - 1])
                    pull += kc * x[block - 1];
                if (block + 1 < n && !ch->slipping_mask[block + 1])
                    pull += kc * x[block + 1];
                double constant = kp * speed * t0 + ch->dashpot * speed
                                  - ch->load * ch->mu_k * ch->direction[block] + pull;
                double p = phi[i * length + j];
                alpha += p * constant;
                beta += p * kp * speed;
                q0 += p * x[block];
                dq0 += p * v[block];
            }
            alpha /= m;
            beta /= m;
            ch->p1[mode] = beta / omega2;
            ch->p0[mode] = (alpha - 2 * gamma * ch->p1[mode]) / omega2;
            ch->c[mode] = q0 - ch->p0[mode];
            ch->d[mode] = (dq0 - ch->p1[mode] + gamma * ch->c[mode]) / ch->omega_d[mode];
        }
    }
}

/* q and dq/dt of modes [from, to) at tau */
static void modal(Chain *ch, double tau, int from, int to)
{
    double decay = exp(-ch->gamma * tau), gamma = ch->gamma;
    for (int k = from; k < to; k++) {
        double wd = ch->omega_d[k], cosine = cos(wd * tau), sine = sin(wd * tau);
        double c = ch->c[k], d = ch->d[k];
        ch->q[k] = ch->p0[k] + ch->p1[k] * tau + decay * (c * cosine + d * sine);
        ch->dq[k] = ch->p1[k] + decay * ((-gamma * c + wd * d) * cosine + (-gamma * d - wd * c) * sine);
    }
}

/* one slipping block's value (``modes`` = ch->q for its position, ch->dq for its speed) */
static double row_value(const Chain *ch, const double *modes, int row)
{
    int r = ch->row_run[row], start = ch->run_start[r], length = ch->run_length[r];
    const double *phi = ch->vectors + ch->run_offset[r] + (row - start) * length;
    double sum = 0.0;
    for (int j = 0; j < length; j++)
        sum += phi[j] * modes[start + j];
    return sum;
}

static double speed_at(Chain *ch, double tau, int row)
{
    int r = ch->row_run[row];
    modal(ch, tau, ch->run_start[r], ch->run_start[r] + ch->run_length[r]);
    return row_value(ch, ch->dq, row);
}

static double position_at(Chain *ch, double tau, int row)
{
    int r = ch->row_run[row];
    modal(ch, tau, ch->run_start[r], ch->run_start[r] + ch->run_length[r]);
    return row_value(ch, ch->q, row);
}

/* a near held block's force at tau (its slipping neighbours' positions from the closed form) */
static double near_force(Chain *ch, double tau, int row, int from_modes)
{
    double force = ch->near_fixed[row] + ch->kp * ch->speed * (ch->t0 + tau);
    for (int k = 0; k < ch->near_moving_count[row]; k++) {
        int moving = ch->near_moving[2 * row + k];
        force += ch->kc * (from_modes ? row_value(ch, ch->q, moving) : position_at(ch, tau, moving));
    }
    return force;
}

/* g > 0 before the change and <= 0 after it: a stopping block's speed along its slip (kind 0), or a
 * joining block's headroom W mu_s - |F| (kind 1) */
static double change(Chain *ch, int kind, int row, double tau)
{
    if (kind == 0)
        return speed_at(ch, tau, row) * ch->direction[ch->index[row]];
    return ch->limit[ch->near_index[row]] - fabs(near_force(ch, tau, row, 0));
}

/* Halvings of a grid interval before a speed within its curvature bound of zero is taken not to cross it
 * (dynamics.DIP_DEPTH) */
#define DIP_DEPTH 20

/* dynamics._dip: the first point of [low, high] where row's change (kind 0: its speed along its slip; kind 1: a
 * near block's headroom), positive at both ends, is at or below zero, and the last positive point before it, in
 * *positive and *nonpositive; 0 where it cannot dip below zero. Between points h apart a function of second
 * derivative at most curvature lies above their chord less curvature h^2 / 8. */
static int dip(Chain *ch, int kind, int row, double low, double at_low, double high, double at_high,
               double curvature, int depth, double *positive, double *nonpositive)
{
    if (fmin(at_low, at_high) > curvature * (high - low) * (high - low) / 8 || depth >= DIP_DEPTH)
        return 0;
    double middle = 0.5 * (low + high), at_middle = change(ch, kind, row, middle);
    if (at_middle <= 0.0) {
        *positive = low;
        *nonpositive = middle;
        return 1;
    }
    return dip(ch, kind, row, low, at_low, middle, at_middle, curvature, depth + 1, positive, nonpositive)
        || dip(ch, kind, row, middle, at_middle, high, at_high, curvature, depth + 1, positive, nonpositive);
}

/* dynamics._Modes.speed_curvature_bound: |d^2 v / d tau^2| of each slipping block at most
 * sum_j |phi_j| sqrt(c_j^2 + d_j^2) (gamma^2 + omega_j^2)^(3/2); and acceleration_bound, |x''| at most
 * sum_j |phi_j| sqrt(c_j^2 + d_j^2) (gamma^2 + omega_j^2). A near block's |F''| is at most k_c times its
 * slipping neighbours' (the plate's pull is linear in time). */
static void curvature_bounds(Chain *ch)
{
    for (int row = 0; row < ch->count; row++) {
        int r = ch->row_run[row], start = ch->run_start[r], length = ch->run_length[r];
        const double *phi = ch->vectors + ch->run_offset[r] + (row - start) * length;
        double bound = 0.0, acceleration = 0.0;
        for (int j = 0; j < length; j++) {
            double w2 = ch->gamma * ch->gamma + ch->omega_d[start + j] * ch->omega_d[start + j];
            double term = fabs(phi[j]) * hypot(ch->c[start + j], ch->d[start + j]) * w2;
            acceleration += term;
            bound += term * sqrt(w2);
        }
        ch->curvature[row] = bound;
        ch->acceleration[row] = acceleration;
    }
    for (int row = 0; row < ch->near_count; row++) {
        double bound = 0.0;
        for (int k = 0; k < ch->near_moving_count[row]; k++)
            bound += ch->kc * ch->acceleration[ch->near_moving[2 * row + k]];
        ch->room_curvature[row] = bound;
    }
}

/* Brent's method on [a, b] (g(a) > 0 >= g(b)) to xtol + rtol |x| */
static double brent(Chain *ch, int kind, int row, double a, double b, double xtol, double rtol)
{
    double xpre = a, xcur = b, fpre = change(ch, kind, row, a), fcur = change(ch, kind, row, b);
    double xblk = 0.0, fblk = 0.0, spre = 0.0, scur = 0.0;
    if (fpre == 0.0)
        return xpre;
    if (fcur == 0.0)
        return xcur;
    for (int iteration = 0; iteration < 200; iteration++) {
        if (fpre != 0.0 && fcur != 0.0 && (signbit(fpre) != signbit(fcur))) {
            xblk = xpre;
            fblk = fpre;
            spre = scur = xcur - xpre;
        }
        if (fabs(fblk) < fabs(fcur)) {
            xpre = xcur; xcur = xblk; xblk = xpre;
            fpre = fcur; fcur = fblk; fblk = fpre;
        }
        double delta = 0.5 * (xtol + rtol * fabs(xcur));
        double bisect = 0.5 * (xblk - xcur);
        if (fcur == 0.0 || fabs(bisect) < delta)
            return xcur;
        if (fabs(spre) > delta && fabs(fcur) < fabs(fpre)) {
            double trial;
            if (xpre == xblk) { /* secant */
                trial = -fcur * (xcur - xpre) / (fcur - fpre);
            } else {            /* inverse quadratic interpolation */
                double dpre = (fpre - fcur) / (xpre - xcur), dblk = (fblk - fcur) / (xblk - xcur);
                trial = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre));
            }
            if (2 * fabs(trial) < fmin(fabs(spre), 3 * fabs(bisect) - delta)) {
                spre = scur;
                scur = trial;
            } else {
                spre = bisect;
                scur = bisect;
            }
        } else {
            spre = bisect;
            scur = bisect;
        }
        xpre = xcur;
        fpre = fcur;
        xcur += fabs(scur) > delta ? scur : (bisect > 0 ? delta : -delta);
        fcur = change(ch, kind, row, xcur);
    }
    return xcur;
}

/* The sub-phase's first change (see the header). Returns tau, -1 if nothing changed within HORIZON_PERIODS of
 * the slowest mode, or -2 if the modes' bounds overflowed (the grid and its dip search would then run without end).
 * Sets stop_flag (rows of S) and join_flag (blocks). */
static double next_change(Chain *ch)
{
    int n = ch->n, count = ch->count;
    double kp = ch->kp, kc = ch->kc, speed = ch->speed, t0 = ch->t0;
    /* near and far held blocks */
    ch->near_count = ch->far_count = 0;
    for (int i = 0; i < n; i++) {
        ch->join_flag[i] = 0;
        if (ch->slipping_mask[i])
            continue;
        int left = i > 0 && ch->slipping_mask[i - 1], right = i + 1 < n && ch->slipping_mask[i + 1];
        if (left || right) {
            int row = ch->near_count++, moving = 0;
            double fixed = ch->force[i] - kp * speed * t0;
            ch->near_index[row] = i;
            if (left) {
                fixed -= kc * ch->x[i - 1];
                ch->near_moving[2 * row + moving++] = ch->position_in_s[i - 1];
            }
            if (right) {
                fixed -= kc * ch->x[i + 1];
                ch->near_moving[2 * row + moving++] = ch->position_in_s[i + 1];
            }
            ch->near_moving_count[row] = moving;
            ch->near_fixed[row] = fixed;
        } else {
            ch->far_index[ch->far_count] = i;
            ch->far_wait[ch->far_count++] = (ch->limit[i] - ch->force[i]) / (kp * speed);
        }
    }
    double fastest = 0.0, slowest = INFINITY, far_first = INFINITY;
    for (int k = 0; k < count; k++) {
        fastest = fmax(fastest, ch->omega_d[k]);
        slowest = fmin(slowest, ch->omega_d[k]);
    }
    for (int k = 0; k < ch->far_count; k++)
        far_first = fmin(far_first, ch->far_wait[k]);
    double step = 2 * M_PI / fastest / SAMPLES, horizon = HORIZON_PERIODS * 2 * M_PI / slowest;
    int candidates = 0;
    long point = 0;
    double low = 0.0, high = 0.0;
    curvature_bounds(ch);
    if (!(isfinite(step) && step > 0 && isfinite(horizon) && far_first > -INFINITY))  /* far_first: +inf if none */
        return -2.0;
    for (int row = 0; row < count; row++)
        if (!isfinite(ch->curvature[row]))
            return -2.0;
    for (int row = 0; row < ch->near_count; row++)
        if (!isfinite(ch->room_curvature[row]))
            return -2.0;
    modal(ch, 0.0, 0, count);
    for (int row = 0; row < count; row++)
        ch->previous[row] = row_value(ch, ch->dq, row) * ch->direction[ch->index[row]];
    for (int row = 0; row < ch->near_count; row++)
        ch->room_previous[row] = ch->limit[ch->near_index[row]] - fabs(near_force(ch, 0.0, row, 1));
    for (;;) {
        point++;
        low = (point - 1) * step;
        if (low >= horizon)
            return -1.0;
        high = point * step;
        modal(ch, high, 0, count);
        for (int row = 0; row < count; row++)
            ch->vs[row] = row_value(ch, ch->dq, row) * ch->direction[ch->index[row]];
        for (int row = 0; row < count; row++) {
            double now = ch->vs[row], before = ch->previous[row], positive, nonpositive;
            if (now <= 0.0) {
                ch->candidate_kind[candidates] = 0;
                ch->candidate_low[candidates] = low;
                ch->candidate_high[candidates] = high;
                ch->candidate_row[candidates++] = row;
            } else if (before > 0.0 && dip(ch, 0, row, low, before, high, now, ch->curvature[row], 0, &positive,
                                           &nonpositive)) {
                /* positive at both grid points, below zero between them: the grid alone would miss the stop */
                ch->candidate_kind[candidates] = 0;
                ch->candidate_low[candidates] = positive;
                ch->candidate_high[candidates] = nonpositive;
                ch->candidate_row[candidates++] = row;
            }
            ch->previous[row] = now;
        }
        modal(ch, high, 0, count);  /* the dips' evaluations moved the modes: the near forces read them at high */
        for (int row = 0; row < ch->near_count; row++)
            ch->room_now[row] = ch->limit[ch->near_index[row]] - fabs(near_force(ch, high, row, 1));
        for (int row = 0; row < ch->near_count; row++) {
            double now = ch->room_now[row], before = ch->room_previous[row], positive, nonpositive;
            if (now <= 0.0) {
                ch->candidate_kind[candidates] = 1;
                ch->candidate_low[candidates] = low;
                ch->candidate_high[candidates] = high;
                ch->candidate_row[candidates++] = row;
            } else if (before > 0.0 && dip(ch, 1, row, low, before, high, now, ch->room_curvature[row], 0,
                                           &positive, &nonpositive)) {
                /* a force within its curvature bound of the limit touched it between the grid points */
                ch->candidate_kind[candidates] = 1;
                ch->candidate_low[candidates] = positive;
                ch->candidate_high[candidates] = nonpositive;
                ch->candidate_row[candidates++] = row;
            }
            ch->room_previous[row] = now;
        }
        if (candidates || far_first <= high)
            break;
    }
    double tau = far_first <= high ? fmax(far_first, 0.0) : INFINITY;
    for (int k = 0; k < candidates; k++) {
        int kind = ch->candidate_kind[k], row = ch->candidate_row[k];
        double root, low = ch->candidate_low[k], high = ch->candidate_high[k], a = low;
        if (!(change(ch, kind, row, low) > 0.0)) {
            a = NAN;
            if (kind == 0) /* a block starting from rest steps off its zero speed first */
                for (int power = 1; power < 40; power++) {
                    double trial = low + (high - low) * ldexp(1.0, -power);
                    if (change(ch, kind, row, trial) > 0.0) {
                        a = trial;
                        break;
                    }
                }
        }
        if (isnan(a))
            root = low;   /* no room before the change: it happens at the bracket's start */
        else if (change(ch, kind, row, high) > 0.0)
            root = high;  /* the grid saw the change and the closed form, to round-off, not quite */
        else
            root = brent(ch, kind, row, a, high, 1e-13 * fmax(high, 1e-300), 4 * EPS);
        ch->candidate_root[k] = root;
        tau = fmin(tau, root);
    }
    /* everything within TOGETHER of tau happens now (identical blocks stop and fail together) */
    modal(ch, tau, 0, count);
    double speed_scale = 1e-300;
    for (int row = 0; row < count; row++) {
        ch->xs[row] = row_value(ch, ch->q, row);
        ch->vs[row] = row_value(ch, ch->dq, row);
        speed_scale = fmax(speed_scale, fmax(fabs(ch->vs[row]), fabs(ch->v[ch->index[row]])));
    }
    for (int row = 0; row < count; row++)
        ch->stop_flag[row] = tau > 0 && ch->vs[row] * ch->direction[ch->index[row]] <= TOGETHER * speed_scale;
    for (int row = 0; row < ch->near_count; row++) {
        double limit = ch->limit[ch->near_index[row]];
        if (fabs(near_force(ch, tau, row, 1)) - limit >= -TOGETHER * fabs(limit))
            ch->join_flag[ch->near_index[row]] = 1;
    }
    for (int k = 0; k < candidates; k++)
        if (ch->candidate_root[k] <= tau) {
            if (ch->candidate_kind[k] == 0)
                ch->stop_flag[ch->candidate_row[k]] = 1;
            else
                ch->join_flag[ch->near_index[ch->candidate_row[k]]] = 1;
        }
    for (int k = 0; k < ch->far_count; k++)
        if (ch->far_wait[k] <= tau * (1 + TOGETHER))
            ch->join_flag[ch->far_index[k]] = 1;
    return tau;
}

/* the largest block speed over the sub-phase, on PEAK_SAMPLES points (a record, not a decision) */
static double peak_speed(Chain *ch, double tau)
{
    double peak = 0.0;
    for (int k = 0; k < PEAK_SAMPLES; k++) {
        modal(ch, tau * k / (PEAK_SAMPLES - 1), 0, ch->count);
        for (int row = 0; row < ch->count; row++)
            peak = fmax(peak, fabs(row_value(ch, ch->dq, row)));
    }
    return peak;
}

/* every position, speed and force finite */
static int finite_state(const Chain *ch, const double *x, const double *v)
{
    for (int i = 0; i < ch->n; i++)
        if (!(isfinite(x[i]) && isfinite(v[i]) && isfinite(ch->force[i])))
            return 0;
    return 1;
}

static void set_slipping(Chain *ch)
{
    ch->count = 0;
    for (int i = 0; i < ch->n; i++) {
        ch->position_in_s[i] = -1;
        if (ch->slipping_mask[i]) {
            ch->position_in_s[i] = ch->count;
            ch->index[ch->count++] = i;
        }
    }
}

static int allocate(Chain *ch)
{
    int n = ch->n;
    size_t doubles = (size_t)n * n + 30 * (size_t)n, ints = 15 * (size_t)n, chars = 4 * (size_t)n;
    double *pool = calloc(doubles, sizeof(double));
    int *ipool = calloc(ints, sizeof(int));
    char *cpool = calloc(chars, 1);
    if (!pool || !ipool || !cpool) {
        free(pool); free(ipool); free(cpool);
        return -1;
    }
    ch->vectors = pool; pool += (size_t)n * n;
    double **d[] = {&ch->omega_d, &ch->p0, &ch->p1, &ch->c, &ch->d, &ch->q, &ch->dq, &ch->xs, &ch->vs, &ch->near_fixed,
                    &ch->far_wait, &ch->force, &ch->direction, &ch->x_before, &ch->curvature, &ch->previous,
                    &ch->acceleration, &ch->room_curvature, &ch->room_previous, &ch->room_now,
                    &ch->candidate_root, &ch->candidate_low, &ch->candidate_high};
    for (size_t k = 0; k < sizeof d / sizeof *d; k++) {
        *d[k] = pool;
        pool += k >= 20 ? 3 * n : n;  /* candidates: a stop a slipping block, a join a near block */
    }
    int **i[] = {&ch->index, &ch->position_in_s, &ch->row_run, &ch->run_start, &ch->run_length, &ch->run_offset,
                 &ch->near_index, &ch->near_moving_count, &ch->far_index, &ch->candidate_kind, &ch->candidate_row,
                 &ch->near_moving};
    for (size_t k = 0; k < sizeof i / sizeof *i; k++) {
        *i[k] = ipool;
        ipool += k == 9 || k == 10 || k == 11 ? 2 * n : n;
    }
    ch->slipping_mask = cpool; ch->slipped = cpool + n; ch->stop_flag = cpool + 2 * n; ch->join_flag = cpool + 3 * n;
    return 0;
}

static PyObject *run(PyObject *self, PyObject *args)
{
    Chain ch;
    memset(&ch, 0, sizeof ch);
    Py_buffer limit, position, start, end, first, size, slip, peak;
    double t;
    long long events, budget, subphases = 0;
    if (!PyArg_ParseTuple(args, "dddddddy*w*dLLw*w*w*w*w*w*", &ch.m, &ch.kp, &ch.kc, &ch.load, &ch.speed, &ch.mu_k,
                          &ch.dashpot, &limit, &position, &t, &events, &budget, &start, &end, &first, &size,
                          &slip, &peak))
        return NULL;
    ch.n = (int)(limit.len / sizeof(double));
    ch.limit = limit.buf;
    ch.gamma = ch.dashpot / (2 * ch.m);
    double *starts = start.buf, *ends = end.buf, *slips = slip.buf, *peaks = peak.buf;
    long long *firsts = first.buf, *sizes = size.buf;
    PyObject *result = NULL;
    int status = DONE;
    long long done = 0;
    double t_start = t;
    double *v = NULL;
    if (allocate(&ch) < 0 || !(v = calloc(ch.n, sizeof(double)))) {
        PyErr_NoMemory();
        goto release;
    }
    int n = ch.n;
    ch.x = position.buf;
    ch.v = v;
    double *x = ch.x, kpv = ch.kp * ch.speed, scale = 0.0;
    double slowest_period = 2 * M_PI * sqrt(ch.m / ch.kp), largest = 0.0;
    for (int i = 0; i < n; i++)
        largest = fmax(largest, ch.limit[i]);
    scale = largest - ch.load * ch.mu_k;
    Py_BEGIN_ALLOW_THREADS
    for (done = 0; done < events; done++) {
        /* stick: the least headroom fails first (and any within TOGETHER of it); a block held past -W mu_s by
         * the start goes backwards at once */
        forces(&ch, x, v, t, ch.force);
        if (!finite_state(&ch, x, v)) {
            status = OVERFLOW;
            goto finished;
        }
        double least = INFINITY;
        for (int i = 0; i < n; i++) {
            double room = ch.force[i] < -ch.limit[i] ? -INFINITY : ch.limit[i] - ch.force[i];
            ch.x_before[i] = room;  /* the headroom, for now */
            least = fmin(least, room);
        }
        double wait = fmax(least, 0.0) / kpv;
        t += wait;
        int first_block = -1;
        double first_room = INFINITY;
        for (int i = 0; i < n; i++) {
            double room = ch.x_before[i] - kpv * wait;
            ch.slipping_mask[i] = room <= TOGETHER * scale;
            if (ch.slipping_mask[i] && room < first_room) {
                first_room = room;
                first_block = i;
            }
            ch.direction[i] = ch.force[i] < -ch.limit[i] ? -1.0 : 1.0;
            ch.x_before[i] = x[i];
            ch.slipped[i] = 0;
        }
        set_slipping(&ch);
        t_start = t;
        double peak_event = 0.0;
        while (ch.count) {
            if (++subphases > budget) {
                status = BUDGET;
                goto finished;
            }
            if (t - t_start > STEADY_PERIODS * slowest_period) {
                status = STEADY;
                goto finished;
            }
            for (int s = 0; s < ch.count; s++)
                ch.slipped[ch.index[s]] = 1;
            build_modes(&ch, t);
            forces(&ch, x, v, t, ch.force);
            if (!finite_state(&ch, x, v)) {
                status = OVERFLOW;
                goto finished;
            }
            double tau = next_change(&ch);
            if (tau < 0) {
                status = tau < -1.5 ? OVERFLOW : NO_CHANGE;
                goto finished;
            }
            peak_event = fmax(peak_event, peak_speed(&ch, tau));
            for (int s = 0; s < ch.count; s++) {
                x[ch.index[s]] = ch.xs[s];
                v[ch.index[s]] = ch.vs[s];
            }
            t += tau;
            for (int s = 0; s < ch.count; s++)
                if (ch.stop_flag[s])
                    v[ch.index[s]] = 0.0;
            forces(&ch, x, v, t, ch.force);
            /* a stopped block holds if its limit does; else it slips on, the way its force pushes */
            for (int s = 0; s < ch.count; s++) {
                int block = ch.index[s];
                if (!ch.stop_flag[s])
                    continue;
                if (fabs(ch.force[block]) > ch.limit[block])
                    ch.direction[block] = ch.force[block] > 0 ? 1.0 : (ch.force[block] < 0 ? -1.0 : 0.0);
                else
                    ch.slipping_mask[block] = 0;
            }
            for (int i = 0; i < n; i++)
                if (ch.join_flag[i]) {
                    ch.direction[i] = ch.force[i] < 0 ? -1.0 : 1.0;
                    ch.slipping_mask[i] = 1;
                }
            set_slipping(&ch);
        }
        starts[done] = t_start;
        ends[done] = t;
        firsts[done] = first_block;
        long long moved = 0;
        for (int i = 0; i < n; i++) {
            moved += ch.slipped[i];
            slips[done * n + i] = x[i] - ch.x_before[i];
        }
        sizes[done] = moved;
        peaks[done] = peak_event;
    }
finished:
    Py_END_ALLOW_THREADS
    {
        PyObject *blocks = PyList_New(0);
        for (int s = 0; blocks && s < ch.count && s < 5; s++) {
            PyObject *block = PyLong_FromLong(ch.index[s]);
            PyList_Append(blocks, block);
            Py_XDECREF(block);
        }
        if (blocks)
            result = Py_BuildValue("iLLddiN", status, done, subphases, t, t_start, ch.count, blocks);
    }
release:
    free(v);
    free(ch.vectors);
    free(ch.index);
    free(ch.slipping_mask);
    PyBuffer_Release(&limit);
    PyBuffer_Release(&position);
    PyBuffer_Release(&start);
    PyBuffer_Release(&end);
    PyBuffer_Release(&first);
    PyBuffer_Release(&size);
    PyBuffer_Release(&slip);
    PyBuffer_Release(&peak);
    return result;
}

static PyMethodDef methods[] = {
    {"run", run, METH_VARARGS,
     "run(mass, leaf_stiffness, coupling_stiffness, normal_load, platform_speed, kinetic_friction, dashpot, limits, "
     "position, t, events, budget, start, end, first, size, slip, peak) -> (status, events done, "
     "sub-phases, t, the last event's start, how many blocks slip, the first five of them). Steps the chain from rest at positions "
     "``position`` (updated in place) and time t; fills the catalogue's buffers."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_chain",
                                    "The spring-block chain's event loop, compiled (see the source's header).", -1,
                                    methods};

PyMODINIT_FUNC PyInit__chain(void)
{
    return PyModule_Create(&module);
}
