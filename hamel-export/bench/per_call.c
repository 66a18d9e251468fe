/* Calls one of the exported robot's CasADi functions CALLS times at a fixed point, for
 * counting its instructions per call under valgrind (instructions.sh):
 *
 *   per_call LIB NAME CALLS
 *
 * The arguments are x, u and p, null for the nominal output (as CasADi passes it), and the
 * seeds: a forward derivative's directions in x and u (null in p; fwd<N>_: N directions,
 * the first one's components scaled by 1, 2, ..., N), an adjoint's weights. Every
 * output is wanted (CasADi asks for every block of jac_adj1 in the parking example's NLP,
 * though its parameters are fixed) except the Jacobian's block by p; with WITHOUT_P=1 in the
 * environment, no block by p of jac_ or jac_adj1_ (what CasADi asks for when the parameters
 * are constants of the NLP's functions). */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef long long casadi_int;
typedef int (*eval_t)(const double**, double**, casadi_int*, double*, int);
typedef casadi_int (*count_t)(void);
typedef const char* (*name_t)(casadi_int);

static const double dx[8] = {0.1, 0.2, -0.3, 0.4, 0.5, -0.6, 0.7, 0.8};
static const double du[2] = {-0.4, 0.9};
static double dxs[64 * 8], dus[64 * 2];
static const double lam[8] = {0.3, -0.1, 0.7, 0.2, -0.5, 1.1, 0.4, -0.9};

static double storage[32][512];

int main(int argc, char** argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s LIB NAME CALLS\n", argv[0]);
        return 2;
    }
    void* lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 2;
    }
    char symbol[256];
    eval_t eval = (eval_t)dlsym(lib, argv[2]);
    snprintf(symbol, sizeof symbol, "%s_n_out", argv[2]);
    count_t n_out = (count_t)dlsym(lib, symbol);
    snprintf(symbol, sizeof symbol, "%s_n_in", argv[2]);
    count_t n_in = (count_t)dlsym(lib, symbol);
    if (!eval || !n_out || !n_in || n_out() > 32 || n_in() > 8) {
        fprintf(stderr, "%s: missing symbols\n", argv[2]);
        return 2;
    }
    static const double x[8] = {0.3, -0.2, 0.25, 1.1, -0.7, 0.4, 0.8, -0.3};
    static const double u[2] = {0.6, -0.2};
    static const double p[9] = {10.0, 1.0, 0.4, 0.3, 0.2, 0.1, 0.5, 0.2, 9.81};
    const double* arg[8] = {x, u, p, NULL, NULL, NULL, NULL, NULL};
    double* res[32];
    /* fwd<N>_: N directions. */
    int directions = 0;
    if (strncmp(argv[2], "fwd", 3) == 0) directions = atoi(argv[2] + 3);
    int forward = directions >= 1 && directions <= 64;
    int second = strncmp(argv[2], "jac_adj1_", 9) == 0;
    int adjoint = second || strncmp(argv[2], "adj1_", 5) == 0;
    int jacobian = !second && strncmp(argv[2], "jac_", 4) == 0;
    if (forward) {
        for (int d = 0; d < directions; ++d) {
            for (int i = 0; i < 8; ++i) dxs[8 * d + i] = (d + 1) * dx[i];
            for (int i = 0; i < 2; ++i) dus[2 * d + i] = (d + 1) * du[i];
        }
        arg[4] = dxs;
        arg[5] = dus;
    }
    if (adjoint) arg[4] = lam;
    snprintf(symbol, sizeof symbol, "%s_name_out", argv[2]);
    name_t name_out = (name_t)dlsym(lib, symbol);
    const char* without_p = getenv("WITHOUT_P");
    for (casadi_int i = 0; i < n_out(); ++i) {
        int wanted = !(jacobian && i == 2);
        if (without_p && strcmp(without_p, "1") == 0 && name_out && (jacobian || second)) {
            const char* name = name_out(i);
            size_t len = strlen(name);
            if ((len >= 2 && strcmp(name + len - 2, "_p") == 0) ||
                strncmp(name, "jac_adj_p_", 10) == 0)
                wanted = 0;
        }
        res[i] = wanted ? storage[i] : NULL;
    }
    long calls = atol(argv[3]);
    for (long k = 0; k < calls; ++k)
        if (eval(arg, res, NULL, NULL, 0)) {
            fprintf(stderr, "evaluation failed\n");
            return 1;
        }
    return 0;
}
