/* A plain C user of an exported hamel model: integrates the robot with a fixed-step RK4 of
 * its own, calling mobile_robot_rhs from libmobile_robot.so, and prints the trajectory as
 * CSV (t then the state, every step, full precision), to compare with hamel's own run.
 *
 *   cc -O2 -I OUTDIR rk4.c -L OUTDIR -lmobile_robot -Wl,-rpath,OUTDIR -o rk4
 *   ./rk4 T_END STEP TAU1 TAU2 X0 ... X7
 */
#include <stdio.h>
#include <stdlib.h>

#include "mobile_robot.h"

#define NX MOBILE_ROBOT_NX

static double p[MOBILE_ROBOT_NP];

/* xdot = F(x, u): a failure (with its message) ends the program. */
static void rhs(const double* x, const double* u, double* xdot) {
    int status = mobile_robot_rhs(0.0, x, NX, u, MOBILE_ROBOT_NU, p, MOBILE_ROBOT_NP, xdot, NX);
    if (status != MOBILE_ROBOT_OK) {
        fprintf(stderr, "mobile_robot_rhs failed (%d): %s\n", status, mobile_robot_last_error());
        exit(1);
    }
}

int main(int argc, char** argv) {
    if (argc != 5 + NX) {
        fprintf(stderr, "usage: %s T_END STEP TAU1 TAU2 X0 ... X%d\n", argv[0], NX - 1);
        return 2;
    }
    double t_end = atof(argv[1]), h = atof(argv[2]);
    double u[MOBILE_ROBOT_NU] = {atof(argv[3]), atof(argv[4])};
    double x[NX], k1[NX], k2[NX], k3[NX], k4[NX], y[NX];
    for (int i = 0; i < NX; ++i) x[i] = atof(argv[5 + i]);
    if (mobile_robot_default_parameters(p, MOBILE_ROBOT_NP) != MOBILE_ROBOT_OK) {
        fprintf(stderr, "%s\n", mobile_robot_last_error());
        return 1;
    }
    /* A dimension the model does not have is refused, with a message. */
    if (mobile_robot_rhs(0.0, x, NX - 1, u, MOBILE_ROBOT_NU, p, MOBILE_ROBOT_NP, y, NX)
        != MOBILE_ROBOT_BAD_DIMENSION) {
        fprintf(stderr, "a wrong length was not refused\n");
        return 1;
    }
    fprintf(stderr, "refused as expected: %s\n", mobile_robot_last_error());
    long steps = (long)(t_end / h + 0.5);
    printf("t");
    for (int i = 0; i < NX; ++i) printf(",x%d", i);
    printf("\n");
    for (long n = 0; n <= steps; ++n) {
        double t = n * h;
        printf("%.17g", t);
        for (int i = 0; i < NX; ++i) printf(",%.17g", x[i]);
        printf("\n");
        if (n == steps) break;
        rhs(x, u, k1);
        for (int i = 0; i < NX; ++i) y[i] = x[i] + 0.5 * h * k1[i];
        rhs(y, u, k2);
        for (int i = 0; i < NX; ++i) y[i] = x[i] + 0.5 * h * k2[i];
        rhs(y, u, k3);
        for (int i = 0; i < NX; ++i) y[i] = x[i] + h * k3[i];
        rhs(y, u, k4);
        for (int i = 0; i < NX; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    return 0;
}
