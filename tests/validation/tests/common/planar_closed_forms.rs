//! Closed-form motions of two catalogue models, for tests that need the exact time at which a
//! quantity crosses a value (events) or the exact state at a time.
//!
//! * The knife edge on a level plane (`KnifeEdge` with `incline = 0`). The catalogue's model
//!   (`hamel-models/src/knife_edge.rs`) has q = (x, y, φ), speeds (v, ω) with ẋ = v cos φ,
//!   ẏ = v sin φ, φ̇ = ω. With no forces the Lagrange–d'Alembert equations are J φ̈ = 0 and
//!   m v̇ = 0 (Neimark & Fufaev, *Dynamics of Nonholonomic Systems*; Bloch, *Nonholonomic
//!   Mechanics and Control*, §1.6, with the plane's slope set to zero; `classic_models.rs`
//!   checks the general inclined case), so v and ω are constant, φ = φ₀ + ωt and, for ω ≠ 0,
//!
//!     x = x₀ + (v/ω)(sin φ − sin φ₀),   y = y₀ − (v/ω)(cos φ − cos φ₀):
//!
//!   the skate runs round a circle of radius |v/ω|.
//!
//! * The Chaplygin sleigh (`ChaplyginSleigh`: q = (x, y, θ), v the forward speed of the
//!   centre of mass, ω = θ̇, the blade a distance a behind the centre of mass). Its reduced
//!   equations (Bloch §1.7, eq. 1.7.6; Neimark & Fufaev ch. III) are
//!
//!     v̇ = a ω²,   ω̇ = −m a v ω / J,   J = I + m a²,
//!
//!   and they conserve E = ½ m v² + ½ J ω² (the centre of mass moves at v e_θ + a ω e_⊥).
//!   Eliminating ω² = (2E − m v²)/J gives a Riccati equation for v alone,
//!
//!     v̇ = k (V² − v²),   k = m a / J,   V = √(2E/m),
//!
//!   whose solution through v₀ (|v₀| < V, i.e. ω₀ ≠ 0) is v = V tanh(kV t + s₀) with
//!   s₀ = artanh(v₀/V): the speed tends to V = √(2E/m), the limit Bloch states, monotonically.
//!   Then ω = sgn(ω₀) √(m/J) V sech(kV t + s₀) (ω keeps its sign: ω̇ is proportional to ω),
//!   and θ = θ₀ + sgn(ω₀) (√(m/J)/k) (gd(kV t + s₀) − gd(s₀)) with the Gudermannian
//!   gd(u) = atan(sinh u) (d gd/du = sech u). Differentiating reproduces the reduced
//!   equations: d/dt V tanh u = kV² sech² u = k(V² − v²), and d/dt sech u = −kV tanh u sech u
//!   gives ω̇ = −k v ω. (This closed form is derived here, not quoted; `sleigh_closed_form_
//!   solves_the_reduced_equations` in `events.rs` checks it by differences.)

/// The knife edge's initial values on a level plane.
#[derive(Clone, Copy, Debug)]
pub struct KnifeStart {
    pub x0: f64,
    pub y0: f64,
    pub phi0: f64,
    pub v: f64,
    pub omega: f64,
}

impl KnifeStart {
    /// The exact state (x, y, φ, v, ω) at time t.
    pub fn state(&self, t: f64) -> [f64; 5] {
        let phi = self.phi0 + self.omega * t;
        let r = self.v / self.omega;
        let x = self.x0 + r * (phi.sin() - self.phi0.sin());
        let y = self.y0 - r * (phi.cos() - self.phi0.cos());
        [x, y, phi, self.v, self.omega]
    }

    /// The time at which φ = c (ω ≠ 0).
    pub fn heading_time(&self, c: f64) -> f64 {
        (c - self.phi0) / self.omega
    }

    /// The value c of x at which sin φ = s on the circle (|s| < 1 for a transversal
    /// crossing): c = x₀ + (v/ω)(s − sin φ₀).
    pub fn x_at_sine(&self, s: f64) -> f64 {
        self.x0 + self.v / self.omega * (s - self.phi0.sin())
    }

    /// The times in (0, t_end] at which x = c, in order, each with whether x is rising there
    /// (ẋ = v cos φ > 0). x = c means sin φ = s = sin φ₀ + (c − x₀) ω/v, so φ = asin s + 2πn
    /// (where cos φ > 0) or φ = π − asin s + 2πn (cos φ < 0). |s| < 1 is required (no
    /// tangency).
    pub fn x_crossings(&self, c: f64, t_end: f64) -> Vec<(f64, bool)> {
        use std::f64::consts::PI;
        let s = self.phi0.sin() + (c - self.x0) * self.omega / self.v;
        assert!(s.abs() < 1.0, "x = {c} is not crossed transversally");
        let base = s.asin();
        let mut out = Vec::new();
        // Enough turns to cover the span either way round.
        let turns = (self.omega.abs() * t_end / (2.0 * PI)).ceil() as i64 + 2;
        for n in -turns..=turns {
            for (phi, cos_positive) in [
                (base + 2.0 * PI * n as f64, true),
                (PI - base + 2.0 * PI * n as f64, false),
            ] {
                let t = (phi - self.phi0) / self.omega;
                if t > 0.0 && t <= t_end {
                    // ẋ = v cos φ.
                    let rising = (self.v > 0.0) == cos_positive;
                    out.push((t, rising));
                }
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }
}

/// The Chaplygin sleigh's closed-form motion (module documentation).
#[derive(Clone, Copy, Debug)]
pub struct SleighMotion {
    pub m: f64,
    /// J = I + m a².
    pub j: f64,
    pub theta0: f64,
    pub omega0: f64,
    /// The limit speed √(2E/m).
    pub limit: f64,
    /// k = m a / J.
    pub k: f64,
    /// s₀ = artanh(v₀/V).
    pub s0: f64,
}

impl SleighMotion {
    /// The motion of a sleigh (m, I, a) from heading θ₀ with speeds (v₀, ω₀), ω₀ ≠ 0.
    pub fn new(m: f64, inertia: f64, a: f64, theta0: f64, v0: f64, omega0: f64) -> Self {
        assert!(omega0 != 0.0, "the closed form needs ω₀ ≠ 0 (|v₀| < V)");
        let j = inertia + m * a * a;
        let energy = 0.5 * m * v0 * v0 + 0.5 * j * omega0 * omega0;
        let limit = (2.0 * energy / m).sqrt();
        SleighMotion {
            m,
            j,
            theta0,
            omega0,
            limit,
            k: m * a / j,
            s0: (v0 / limit).atanh(),
        }
    }

    fn u(&self, t: f64) -> f64 {
        self.k * self.limit * t + self.s0
    }

    /// v(t) = V tanh(kV t + s₀).
    pub fn v(&self, t: f64) -> f64 {
        self.limit * self.u(t).tanh()
    }

    /// ω(t) = sgn(ω₀) √(m/J) V sech(kV t + s₀).
    pub fn omega(&self, t: f64) -> f64 {
        self.omega0.signum() * (self.m / self.j).sqrt() * self.limit / self.u(t).cosh()
    }

    /// θ(t) = θ₀ + sgn(ω₀) (√(m/J)/k) (gd(kV t + s₀) − gd(s₀)).
    pub fn theta(&self, t: f64) -> f64 {
        let gd = |u: f64| u.sinh().atan();
        self.theta0
            + self.omega0.signum() * (self.m / self.j).sqrt() / self.k
                * (gd(self.u(t)) - gd(self.s0))
    }

    /// The time at which v = f V (|f| < 1).
    pub fn speed_time(&self, fraction: f64) -> f64 {
        (fraction.atanh() - self.s0) / (self.k * self.limit)
    }

    /// The time at which θ = c (between θ₀ and its limit).
    pub fn heading_time(&self, c: f64) -> f64 {
        let g = self.omega0.signum() * (c - self.theta0) * self.k / (self.m / self.j).sqrt()
            + self.s0.sinh().atan();
        // gd(u) = g ⇒ u = asinh(tan g).
        (g.tan().asinh() - self.s0) / (self.k * self.limit)
    }
}
