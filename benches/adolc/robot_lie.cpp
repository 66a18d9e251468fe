// The mobile robot's Lie derivatives by ADOL-C's Lie drivers (lie_scalarcv, lie_gradientcv:
// Röbenack's algorithms on taped vector fields), side by side with hamel's generated
// `lie_values`: the same look-ahead point 0.3 m ahead of the axle, the same 64 states.
// Built and run by `benches/adolc_lie.sh`, which says what it prints.
//
// The robot's reduced ODE is written out by hand as in
// tests/validation/tests/common/robot_closed_form.rs (hamel::docs::design's equations),
// the default parameters of hamel::models::MobileRobot. ADOL-C tapes the drift f = F(x, 0),
// the input fields g_j = ∂F/∂u_j and the outputs h; then
//   L_f^k h, k = 0 … 2           lie_scalarcv(f, h, d = 2)
//   ∇ L_f^k h, k = 0, 1          lie_gradientcv(f, h, d = 1)
//   L_{g_j} L_f^k h = ∇ L_f^k h · g_j, g_j(x) by zos_forward on its tape,
// everything hamel's lie_values returns.

#include <adolc/adolc.h>
#include <adolc/lie/drivers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

const int N = 8, M = 2, R = 2;
const short TAPE_F = 1, TAPE_H = 2, TAPE_G1 = 3, TAPE_G2 = 4;

struct Robot {
    double m0 = 10.0, mw = 1.0, jx = 0.4, jy = 0.3, jz = 0.2, r = 0.1, b = 0.5, l = 0.2,
           g = 9.81;
};

// ẋ = F(x, u) for x = (x, y, α, φ₁, φ₂, ω³, ω⁴, ω⁵), u = (τ₁, τ₂); T is double or adouble.
// With `field` = j + 1 it is ∂F/∂u_j instead (F is affine in u).
template <class T>
void rhs(const Robot& p, const T* x, const double* u, int field, T* dx) {
    T alpha = x[2], w3 = x[5], w4 = x[6], w5 = x[7];
    T theta = p.r * (x[3] - x[4]) / p.b;
    T st = sin(theta), ct = cos(theta), sa = sin(alpha), ca = cos(alpha);
    double ml = p.m0 * p.l, ml2 = ml * p.l;
    T j5 = (p.jx + ml2) * sa * sa + p.jz * ca * ca + 0.75 * p.mw * p.b * p.b +
           0.5 * p.mw * p.r * p.r;
    double torque = u[0] + u[1];
    T k_sin2a = (p.jx - p.jz + ml2) * 2.0 * sa * ca;
    T r3, r4, r5;
    if (field == 0) {
        r3 = -torque + 0.5 * k_sin2a * w5 * w5 + ml * p.g * sa;
        r4 = torque / p.r + ml * sa * (w3 * w3 + w5 * w5);
        r5 = p.b * (u[0] - u[1]) / (2.0 * p.r) - k_sin2a * w3 * w5 - ml * sa * w4 * w5;
    } else {
        double sign = field == 1 ? 1.0 : -1.0;
        r3 = -1.0;
        r4 = 1.0 / p.r;
        r5 = sign * p.b / (2.0 * p.r);
    }
    double a = p.jy + ml2, d = p.m0 + 3.0 * p.mw;
    T c = ml * ca;
    T inv_det = 1.0 / (a * d - c * c);
    if (field == 0) {
        T roll = w4 / p.r - w3, turn = 0.5 * p.b / p.r * w5;
        dx[0] = ct * w4;
        dx[1] = st * w4;
        dx[2] = w3;
        dx[3] = roll + turn;
        dx[4] = roll - turn;
    } else {
        for (int i = 0; i < 5; ++i) dx[i] = 0.0;
    }
    dx[5] = (d * r3 - c * r4) * inv_det;
    dx[6] = (a * r4 - c * r3) * inv_det;
    dx[7] = r5 / j5;
}

template <class T>
void look_ahead(const Robot& p, const T* x, T* y) {
    T theta = (x[3] - x[4]) * (p.r / p.b);
    y[0] = x[0] + cos(theta) * 0.3;
    y[1] = x[1] + sin(theta) * 0.3;
}

void tape_field(const Robot& p, short tag, int field, const double* x0) {
    const double zero[M] = {0.0, 0.0};
    trace_on(tag);
    adouble x[N], dx[N];
    double out[N];
    for (int i = 0; i < N; ++i) x[i] <<= x0[i];
    rhs(p, x, zero, field, dx);
    for (int i = 0; i < N; ++i) dx[i] >>= out[i];
    trace_off();
}

void tape_outputs(const Robot& p, const double* x0) {
    trace_on(TAPE_H);
    adouble x[N], y[R];
    double out[R];
    for (int i = 0; i < N; ++i) x[i] <<= x0[i];
    look_ahead(p, x, y);
    for (int i = 0; i < R; ++i) y[i] >>= out[i];
    trace_off();
}

// What hamel's lie_values gives: L_f^k h_i at k·R + i (k ≤ 2), then L_{g_j} L_f^k h_i at
// (k·R + i)·M + j (k < 2).
struct Lie {
    double** scalar = myalloc2(R, 3);
    double*** gradient = myalloc3(R, N, 2);
    double fields[M][N];

    void at(double* x, std::vector<double>& out) {
        lie_scalarcv(TAPE_F, TAPE_H, N, R, x, 2, scalar);
        lie_gradientcv(TAPE_F, TAPE_H, N, R, x, 1, gradient);
        zos_forward(TAPE_G1, N, N, 0, x, fields[0]);
        zos_forward(TAPE_G2, N, N, 0, x, fields[1]);
        out.clear();
        for (int k = 0; k <= 2; ++k)
            for (int i = 0; i < R; ++i) out.push_back(scalar[i][k]);
        for (int k = 0; k < 2; ++k)
            for (int i = 0; i < R; ++i)
                for (int j = 0; j < M; ++j) {
                    double s = 0.0;
                    for (int l = 0; l < N; ++l) s += gradient[i][l][k] * fields[j][l];
                    out.push_back(s);
                }
    }
};

double seconds_per_call(int calls, const std::function<void()>& f) {
    auto start = std::chrono::steady_clock::now();
    for (int c = 0; c < calls; ++c) f();
    std::chrono::duration<double> d = std::chrono::steady_clock::now() - start;
    return d.count() / calls;
}

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(q * (v.size() - 1) + 0.5)];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: robot_lie VALUES_FILE ROUNDS (VALUES_FILE from benches/lie.rs "
                     "with HAMEL_LIE_VALUES set)\n";
        return 2;
    }
    std::ifstream file(argv[1]);
    int rounds = std::stoi(argv[2]);
    std::vector<std::vector<double>> states, hamel;
    for (std::string line; std::getline(file, line);) {
        std::istringstream words(line);
        std::vector<double> v;
        for (double d; words >> d;) v.push_back(d);
        if (v.size() != N + 6 + 8) {
            std::cerr << "a line of " << v.size() << " numbers in " << argv[1]
                      << ", not " << N + 6 + 8 << "\n";
            return 1;
        }
        states.emplace_back(v.begin(), v.begin() + N);
        hamel.emplace_back(v.begin() + N, v.end());
    }
    if (states.empty()) {
        std::cerr << "no states in " << argv[1] << "\n";
        return 1;
    }
    Robot p;
    tape_field(p, TAPE_F, 0, states[0].data());
    tape_field(p, TAPE_G1, 1, states[0].data());
    tape_field(p, TAPE_G2, 2, states[0].data());
    tape_outputs(p, states[0].data());

    // The values against hamel's, relative to the largest of each kind at the state.
    Lie lie;
    std::vector<double> values;
    double worst = 0.0;
    for (size_t s = 0; s < states.size(); ++s) {
        lie.at(states[s].data(), values);
        for (auto [from, to] : {std::pair{0, 6}, std::pair{6, 14}}) {
            double scale = 0.0, diff = 0.0;
            for (int i = from; i < to; ++i) {
                scale = std::max(scale, std::fabs(hamel[s][i]));
                diff = std::max(diff, std::fabs(values[i] - hamel[s][i]));
            }
            worst = std::max(worst, diff / scale);
        }
    }
    std::printf("ADOL-C against hamel at %zu states: largest relative difference %.1e\n",
                states.size(), worst);

    // Interleaved: a batch of the hand-written right-hand side over the states, then a batch
    // of the Lie drivers; the figure is the median over the rounds of the per-round ratio.
    const double u[M] = {0.3, -0.2};
    double dx[N];
    double sink = 0.0;
    auto rhs_batch = [&] {
        for (auto& x : states) {
            rhs(p, x.data(), u, 0, dx);
            sink += dx[7];
        }
    };
    auto lie_batch = [&] {
        for (auto& x : states) {
            lie.at(x.data(), values);
            sink += values[13];
        }
    };
    // Calls per batch: about a millisecond each.
    auto calls = [](const std::function<void()>& f) {
        double t = seconds_per_call(3, f);
        return std::max(1, static_cast<int>(1e-3 / t));
    };
    int rhs_calls = calls(rhs_batch), lie_calls = calls(lie_batch);
    std::vector<double> rhs_ns, lie_ns, ratios;
    for (int r = 0; r < rounds; ++r) {
        double a = seconds_per_call(rhs_calls, rhs_batch) / states.size() * 1e9;
        double b = seconds_per_call(lie_calls, lie_batch) / states.size() * 1e9;
        rhs_ns.push_back(a);
        lie_ns.push_back(b);
        ratios.push_back(b / a);
    }
    std::printf("robot, %d rounds: hand-written C++ rhs %.0f ns a state; ADOL-C's Lie drivers "
                "(L_f^k h, k <= 2, and L_g L_f^k h, k < 2) %.0f ns = %.1f rhs (p10-p90 "
                "%.1f-%.1f)%s\n",
                rounds, percentile(rhs_ns, 0.5), percentile(lie_ns, 0.5),
                percentile(ratios, 0.5), percentile(ratios, 0.1), percentile(ratios, 0.9),
                sink == 12345.0 ? " " : "");
    return worst <= 1e-12 ? 0 : 1;
}
