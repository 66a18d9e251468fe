/* Speed of CasADi external functions, hamel's against CasADi's own generated C, called as
 * CasADi calls them (arrays of pointers), loaded with dlopen:
 *
 *   external_speed LIB_A NAME_A LIB_B NAME_B [ROUNDS] [BATCH]
 *
 * For each of f, jac_f (every block), f + jac_f, fwd1_f (a direction in x and u, none in p)
 * and jac_adj1_f (every block: what CasADi asks for in the parking example's NLP, though its
 * parameters are fixed), alternates batches of BATCH calls of A and of B,
 * ROUNDS times, and prints the median time per call of each and the median of the per-round
 * ratios B/A with its 10th and 90th percentiles (interleaved: the machine's drift hits both).
 * The point is a fixed state, input and the parameters given on the command line's defaults. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef long long casadi_int;
typedef int (*eval_t)(const double**, double**, casadi_int*, double*, int);
typedef casadi_int (*count_t)(void);
typedef const casadi_int* (*sparsity_t)(casadi_int);

struct function {
    eval_t eval;
    casadi_int n_in, n_out;
    const double* arg[16];
    double* res[32];
};

static double storage[128][512];

static void load(void* lib, const char* name, struct function* f) {
    char symbol[256];
    f->eval = (eval_t)dlsym(lib, name);
    snprintf(symbol, sizeof symbol, "%s_n_in", name);
    count_t n_in = (count_t)dlsym(lib, symbol);
    snprintf(symbol, sizeof symbol, "%s_n_out", name);
    count_t n_out = (count_t)dlsym(lib, symbol);
    if (!f->eval || !n_in || !n_out) {
        fprintf(stderr, "%s: missing symbols\n", name);
        exit(2);
    }
    f->n_in = n_in();
    f->n_out = n_out();
}

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int compare(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static double quantile(double* v, int n, double q) {
    qsort(v, n, sizeof *v, compare);
    return v[(int)(q * (n - 1) + 0.5)];
}

static const double x[8] = {0.3, -0.2, 0.25, 1.1, -0.7, 0.4, 0.8, -0.3};
static const double u[2] = {0.6, -0.2};
static const double p[9] = {10.0, 1.0, 0.4, 0.3, 0.2, 0.1, 0.5, 0.2, 9.81};
static const double lam[8] = {0.3, -0.1, 0.7, 0.2, -0.5, 1.1, 0.4, -0.9};
static const double dx[8] = {0.1, 0.2, -0.3, 0.4, 0.5, -0.6, 0.7, 0.8};
static const double du[2] = {-0.4, 0.9};

enum seeds { NONE, FORWARD, ADJOINT };

/* Arguments: x, u, p, null for the nominal output, then the seeds the function takes (a
 * direction in x and u; the adjoint's weights); every output wanted. */
static void prepare(struct function* f, int slot, enum seeds seeds) {
    f->arg[0] = x;
    f->arg[1] = u;
    f->arg[2] = p;
    for (int i = 3; i < f->n_in; ++i) f->arg[i] = NULL;
    if (seeds == FORWARD) {
        f->arg[4] = dx;
        f->arg[5] = du;
    }
    if (seeds == ADJOINT) f->arg[4] = lam;
    for (int i = 0; i < f->n_out; ++i) f->res[i] = storage[slot * 16 + (i % 16)];
}

static double batch(struct function** fs, int count, int calls) {
    double start = now();
    for (int k = 0; k < calls; ++k)
        for (int j = 0; j < count; ++j)
            if (fs[j]->eval(fs[j]->arg, fs[j]->res, NULL, NULL, 0)) {
                fprintf(stderr, "evaluation failed\n");
                exit(1);
            }
    return (now() - start) / calls;
}

int main(int argc, char** argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: %s LIB_A NAME_A LIB_B NAME_B [ROUNDS] [BATCH]\n", argv[0]);
        return 2;
    }
    int rounds = argc > 5 ? atoi(argv[5]) : 31, calls = argc > 6 ? atoi(argv[6]) : 20000;
    void* libs[2] = {dlopen(argv[1], RTLD_NOW | RTLD_LOCAL), dlopen(argv[3], RTLD_NOW | RTLD_LOCAL)};
    const char* names[2] = {argv[2], argv[4]};
    if (!libs[0] || !libs[1]) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 2;
    }
    const char* kinds[5] = {"f", "jac_f", "f + jac_f", "fwd1_f", "jac_adj1_f"};
    struct function fn[2][4];
    for (int m = 0; m < 2; ++m) {
        char name[256];
        load(libs[m], names[m], &fn[m][0]);
        snprintf(name, sizeof name, "jac_%s", names[m]);
        load(libs[m], name, &fn[m][1]);
        snprintf(name, sizeof name, "fwd1_%s", names[m]);
        load(libs[m], name, &fn[m][2]);
        snprintf(name, sizeof name, "jac_adj1_%s", names[m]);
        load(libs[m], name, &fn[m][3]);
        prepare(&fn[m][0], m * 4 + 0, NONE);
        prepare(&fn[m][1], m * 4 + 1, NONE);
        prepare(&fn[m][2], m * 4 + 2, FORWARD);
        prepare(&fn[m][3], m * 4 + 3, ADJOINT);
    }
    printf("%-18s %12s %12s %10s %17s\n", "function", "A (ns/call)", "B (ns/call)", "B/A", "p10-p90 of B/A");
    for (int k = 0; k < 5; ++k) {
        double ta[1024], tb[1024], ratio[1024];
        for (int r = 0; r < rounds; ++r) {
            for (int m = 0; m < 2; ++m) {
                struct function* list[2];
                int count = 1;
                if (k == 0) list[0] = &fn[m][0];
                else if (k == 1) list[0] = &fn[m][1];
                else if (k == 2) { list[0] = &fn[m][0]; list[1] = &fn[m][1]; count = 2; }
                else if (k == 3) list[0] = &fn[m][2];
                else list[0] = &fn[m][3];
                int n = k == 4 ? calls / 10 : calls;
                double t = batch(list, count, n);
                if (m == 0) ta[r] = t; else tb[r] = t;
            }
            ratio[r] = tb[r] / ta[r];
        }
        double ma = quantile(ta, rounds, 0.5), mb = quantile(tb, rounds, 0.5);
        double lo = quantile(ratio, rounds, 0.1), mid = quantile(ratio, rounds, 0.5), hi = quantile(ratio, rounds, 0.9);
        printf("%-18s %12.1f %12.1f %10.2f %8.2f-%.2f\n", kinds[k], 1e9 * ma, 1e9 * mb, mid, lo, hi);
    }
    return 0;
}
