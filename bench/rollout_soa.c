/* The C anchor of bench/integrate.py: a batch rollout of free rigid bodies written the way a
 * C programmer would for speed.  Structure of arrays, bodies in chunks of CHUNK that stay in
 * L1 while all steps run, no allocation per step.  Same step as inertia's rollout: RK4 (or the
 * Strang splitting) on (q, m = I w) in the principal frame, renormalised q, and the exact
 * translation under a held world force.  Built by hand by bench/integrate.py:
 *     cc -O3 -march=native -fno-math-errno -shared -fPIC rollout_soa.c -o rollout_soa.so -lm
 * Not part of the package.
 */
#include <math.h>
#include <string.h>

#define CHUNK 128

typedef struct {
    double p[3][CHUNK], v[3][CHUNK], q[4][CHUNK], m[3][CHUNK];
} chunk_t;

static inline void rk4_rate(double qw, double qx, double qy, double qz, double m0, double m1, double m2,
                            double W0, double W1, double W2, double *dq, double *dm) {
    double a = m0 * W0, b = m1 * W1, c = m2 * W2;
    dq[0] = 0.5 * (-qx * a - qy * b - qz * c);
    dq[1] = 0.5 * (qw * a + qy * c - qz * b);
    dq[2] = 0.5 * (qw * b - qx * c + qz * a);
    dq[3] = 0.5 * (qw * c + qx * b - qy * a);
    dm[0] = m1 * c - m2 * b;
    dm[1] = m2 * a - m0 * c;
    dm[2] = m0 * b - m1 * a;
}

static void chunk_rk4(chunk_t *s, const double *I, const double *acc, double h) {
    const double W0 = 1.0 / I[0], W1 = 1.0 / I[1], W2 = 1.0 / I[2];
    const double h2 = 0.5 * h, h6 = h / 6.0, hh = 0.5 * h * h;

    for (int i = 0; i < CHUNK; i++) {
        double q[4] = {s->q[0][i], s->q[1][i], s->q[2][i], s->q[3][i]};
        double m[3] = {s->m[0][i], s->m[1][i], s->m[2][i]};
        double k1q[4], k1m[3], k2q[4], k2m[3], k3q[4], k3m[3], k4q[4], k4m[3];
        rk4_rate(q[0], q[1], q[2], q[3], m[0], m[1], m[2], W0, W1, W2, k1q, k1m);
        rk4_rate(q[0] + h2 * k1q[0], q[1] + h2 * k1q[1], q[2] + h2 * k1q[2], q[3] + h2 * k1q[3],
                 m[0] + h2 * k1m[0], m[1] + h2 * k1m[1], m[2] + h2 * k1m[2], W0, W1, W2, k2q, k2m);
        rk4_rate(q[0] + h2 * k2q[0], q[1] + h2 * k2q[1], q[2] + h2 * k2q[2], q[3] + h2 * k2q[3],
                 m[0] + h2 * k2m[0], m[1] + h2 * k2m[1], m[2] + h2 * k2m[2], W0, W1, W2, k3q, k3m);
        rk4_rate(q[0] + h * k3q[0], q[1] + h * k3q[1], q[2] + h * k3q[2], q[3] + h * k3q[3],
                 m[0] + h * k3m[0], m[1] + h * k3m[1], m[2] + h * k3m[2], W0, W1, W2, k4q, k4m);
        double r[4], n2 = 0.0;
        for (int k = 0; k < 4; k++) {
            r[k] = q[k] + h6 * (k1q[k] + 2.0 * (k2q[k] + k3q[k]) + k4q[k]);
            n2 += r[k] * r[k];
        }
        double inv = 1.0 / sqrt(n2);
        for (int k = 0; k < 4; k++) s->q[k][i] = r[k] * inv;
        for (int k = 0; k < 3; k++) {
            s->m[k][i] = m[k] + h6 * (k1m[k] + 2.0 * (k2m[k] + k3m[k]) + k4m[k]);
            s->p[k][i] += s->v[k][i] * h + acc[k] * hh;
            s->v[k][i] += acc[k] * h;
        }
    }
}

static inline void rotor(double *q0, double *qj, double *qk, double *ql, double mj, double *mk, double *ml,
                         double Wj, double dt) {
    double half = 0.5 * dt * mj * Wj, sh = sin(half), ch = cos(half);
    double s = 2.0 * sh * ch, c = 1.0 - 2.0 * sh * sh;
    double a = *q0, b = *qj, d = *qk, e = *ql, f = *mk, g = *ml;
    *q0 = a * ch - b * sh; *qj = b * ch + a * sh; *qk = d * ch + e * sh; *ql = e * ch - d * sh;
    *mk = c * f + s * g; *ml = c * g - s * f;
}

static void chunk_splitting(chunk_t *s, const double *I, const double *acc, double h) {
    const double W0 = 1.0 / I[0], W1 = 1.0 / I[1], W2 = 1.0 / I[2], hh = 0.5 * h * h;

    for (int i = 0; i < CHUNK; i++) {
        double qw = s->q[0][i], qx = s->q[1][i], qy = s->q[2][i], qz = s->q[3][i];
        double m0 = s->m[0][i], m1 = s->m[1][i], m2 = s->m[2][i];
        rotor(&qw, &qx, &qy, &qz, m0, &m1, &m2, W0, 0.5 * h);
        rotor(&qw, &qy, &qz, &qx, m1, &m2, &m0, W1, 0.5 * h);
        rotor(&qw, &qz, &qx, &qy, m2, &m0, &m1, W2, h);
        rotor(&qw, &qy, &qz, &qx, m1, &m2, &m0, W1, 0.5 * h);
        rotor(&qw, &qx, &qy, &qz, m0, &m1, &m2, W0, 0.5 * h);
        double inv = 1.0 / sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
        s->q[0][i] = qw * inv; s->q[1][i] = qx * inv; s->q[2][i] = qy * inv; s->q[3][i] = qz * inv;
        s->m[0][i] = m0; s->m[1][i] = m1; s->m[2][i] = m2;
        for (int k = 0; k < 3; k++) {
            s->p[k][i] += s->v[k][i] * h + acc[k] * hh;
            s->v[k][i] += acc[k] * h;
        }
    }
}

/* x: (N, 13) states [p, v, q, w] in the principal frame, replaced by the final states; N a
 * multiple of CHUNK; I (3) shared moments; force (3) held world force; mass; gravity (3). */
void rollout(int method, long N, long n_steps, double h, double *x, const double *I, const double *force,
             double mass, const double *gravity) {
    chunk_t s;
    double acc[3] = {force[0] / mass + gravity[0], force[1] / mass + gravity[1], force[2] / mass + gravity[2]};
    for (long b0 = 0; b0 + CHUNK <= N; b0 += CHUNK) {
        for (int i = 0; i < CHUNK; i++) {
            const double *r = x + 13 * (b0 + i);
            for (int k = 0; k < 3; k++) { s.p[k][i] = r[k]; s.v[k][i] = r[3 + k]; s.m[k][i] = I[k] * r[10 + k]; }
            for (int k = 0; k < 4; k++) s.q[k][i] = r[6 + k];
        }
        for (long t = 0; t < n_steps; t++) {
            if (method == 0) chunk_rk4(&s, I, acc, h);
            else chunk_splitting(&s, I, acc, h);
        }
        for (int i = 0; i < CHUNK; i++) {
            double *r = x + 13 * (b0 + i);
            for (int k = 0; k < 3; k++) { r[k] = s.p[k][i]; r[3 + k] = s.v[k][i]; r[10 + k] = s.m[k][i] / I[k]; }
            for (int k = 0; k < 4; k++) r[6 + k] = s.q[k][i];
        }
    }
}
