//! The driver's seat as a linear filter from the floor under the seat to the seat
//! surface, vertical only: a cushion (spring and damper) between the floor and the seat
//! surface, carrying the seated occupant's apparent mass.
//!
//! The occupant is the single-degree-of-freedom apparent-mass model of Fairley and
//! Griffin (1989, J. Biomech. 22, 81-94): a mass `m0` that moves with the seat surface
//! and a mass `m1` on a spring and damper, natural frequency 5 Hz (31.4 rad/s) and
//! damping ratio 0.475, as given by Brammer and Peterson, "Vibration, mechanical shock,
//! and impact", in Kutz (ed.), Biomedical Engineering and Design Handbook, vol. 1, 2nd
//! ed., McGraw-Hill 2009, chapter 11, p. 272 (fig. 11.7). The cushion and the mass
//! split are the vehicle file's (`[seat]`, each value with its source class).
//!
//! With Z_c = k_c + c_c s the cushion's force per relative displacement and
//! M(s) = m0 + m1 (k1 + c1 s) / (m1 s^2 + c1 s + k1) the occupant's apparent mass, the
//! force balance at the seat surface, Z_c (x_floor - x_seat) = s^2 M x_seat, gives the
//! transmissibility
//!
//! ```text
//! T(s) = a_seat / a_floor = Z_c / (Z_c + s^2 M(s))
//! ```
//!
//! In the time domain the same model is four states (seat surface and moving mass,
//! displacement and velocity relative to the floor) driven by the floor acceleration,
//! discretised exactly for an input linear between samples (first-order hold, by one
//! matrix exponential: Franklin, Powell and Workman, Digital Control of Dynamic
//! Systems, 3rd ed., 1998, section 6.3.2). The seat is not coupled back into the car
//! (`docs/comfort.md` says why that is acceptable). Fore-aft and lateral pass through.

use nalgebra::{Complex, DMatrix, Matrix4, Vector4};
use serde::{Deserialize, Serialize};

use towride_mbs::input::{InputError, Seg, Source};

/// The `[seat]` section of a car body file, as written.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SeatSpec {
    /// The occupant's mass on the seat cushion (the apparent mass at low frequency) [kg].
    pub occupant_mass_kg: f64,
    /// The share of it on the occupant's spring (m1 / (m0 + m1)), below 1 [-].
    pub occupant_moving_fraction: f64,
    /// Natural frequency of the occupant's moving mass on a rigid seat [Hz].
    pub occupant_natural_frequency_hz: f64,
    /// Damping ratio of the occupant's moving mass [-].
    pub occupant_damping_ratio: f64,
    /// Cushion stiffness, vertical [N/m].
    pub cushion_stiffness_n_m: f64,
    /// Cushion damping, vertical [N s/m].
    pub cushion_damping_n_s_m: f64,
}

/// A checked seat with its occupant, in SI.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Seat {
    /// The mass moving with the seat surface, m0 [kg].
    pub frame_mass_kg: f64,
    /// The occupant's moving mass, m1 [kg].
    pub moving_mass_kg: f64,
    /// The occupant's spring, k1 = m1 (2 pi f0)^2 [N/m].
    pub occupant_stiffness_n_m: f64,
    /// The occupant's damper, c1 = 2 zeta sqrt(k1 m1) [N s/m].
    pub occupant_damping_n_s_m: f64,
    /// Cushion stiffness [N/m].
    pub cushion_stiffness_n_m: f64,
    /// Cushion damping [N s/m].
    pub cushion_damping_n_s_m: f64,
}

fn at(base: &[Seg], key: &str) -> Vec<Seg> {
    let mut p = base.to_vec();
    p.push(Seg::from(key));
    p
}

impl SeatSpec {
    /// The seat in SI, or an error at the field (file, line) that is out of range.
    pub fn check(&self, src: &Source, p: &[Seg]) -> Result<Seat, InputError> {
        let m = src.positive(&at(p, "occupant_mass_kg"), self.occupant_mass_kg)?;
        let fr = src.positive(
            &at(p, "occupant_moving_fraction"),
            self.occupant_moving_fraction,
        )?;
        if fr >= 1.0 {
            // A massless seat surface would make the model algebraic, not a filter.
            return Err(src.error(
                &at(p, "occupant_moving_fraction"),
                format!("must be below 1 (some mass moves with the seat surface), got {fr}"),
            ));
        }
        let f0 = src.positive(
            &at(p, "occupant_natural_frequency_hz"),
            self.occupant_natural_frequency_hz,
        )?;
        let zeta = src.non_negative(
            &at(p, "occupant_damping_ratio"),
            self.occupant_damping_ratio,
        )?;
        let kc = src.positive(&at(p, "cushion_stiffness_n_m"), self.cushion_stiffness_n_m)?;
        let cc = src.non_negative(&at(p, "cushion_damping_n_s_m"), self.cushion_damping_n_s_m)?;
        Ok(Seat::new(m, fr, f0, zeta, kc, cc))
    }
}

/// Reads the `[seat]` section of `file` (a car body file); an error names the file, and
/// the line and field of a bad value, or says the section is missing.
pub fn read(file: &std::path::Path) -> Result<Seat, InputError> {
    let src = Source::read(file)?;
    match src.parse_key::<SeatSpec>("seat")? {
        Some(s) => s.check(&src, &[Seg::from("seat")]),
        None => Err(src.error(&[Seg::from("seat")], "no [seat] section in this file")),
    }
}

impl Seat {
    /// The seat from the occupant's mass `m` on the cushion, its moving share `fr`,
    /// natural frequency `f0` [Hz] and damping ratio `zeta`, and the cushion's `kc`, `cc`.
    pub fn new(m: f64, fr: f64, f0: f64, zeta: f64, kc: f64, cc: f64) -> Seat {
        let m1 = fr * m;
        let k1 = m1 * (2.0 * std::f64::consts::PI * f0).powi(2);
        Seat {
            frame_mass_kg: m - m1,
            moving_mass_kg: m1,
            occupant_stiffness_n_m: k1,
            occupant_damping_n_s_m: 2.0 * zeta * (k1 * m1).sqrt(),
            cushion_stiffness_n_m: kc,
            cushion_damping_n_s_m: cc,
        }
    }

    /// The occupant's apparent mass on a rigid seat at `f` [Hz] [kg].
    pub fn apparent_mass(&self, f: f64) -> Complex<f64> {
        let s = Complex::new(0.0, 2.0 * std::f64::consts::PI * f);
        let (m1, k1, c1) = (
            self.moving_mass_kg,
            self.occupant_stiffness_n_m,
            self.occupant_damping_n_s_m,
        );
        self.frame_mass_kg + m1 * (k1 + c1 * s) / (m1 * s * s + c1 * s + k1)
    }

    /// The transmissibility T = a_seat / a_floor at `f` [Hz] (module docs).
    pub fn transmissibility(&self, f: f64) -> Complex<f64> {
        let s = Complex::new(0.0, 2.0 * std::f64::consts::PI * f);
        let zc = self.cushion_stiffness_n_m + self.cushion_damping_n_s_m * s;
        zc / (zc + s * s * self.apparent_mass(f))
    }

    /// The frequency [Hz] and value of the largest |T| over 0.1-80 Hz (a 1 mHz grid
    /// refined by golden section), the seat's resonance as a table would quote it.
    pub fn resonance(&self) -> (f64, f64) {
        let g = |f: f64| self.transmissibility(f).norm();
        let mut best = (0.1, g(0.1));
        let mut f = 0.1;
        while f <= 80.0 {
            let v = g(f);
            if v > best.1 {
                best = (f, v);
            }
            f += 0.01;
        }
        let (mut a, mut b) = (best.0 - 0.01, best.0 + 0.01);
        let r = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (x1, x2) = (b - r * (b - a), a + r * (b - a));
            if g(x1) > g(x2) {
                b = x2;
            } else {
                a = x1;
            }
        }
        let fm = 0.5 * (a + b);
        (fm, g(fm))
    }

    /// The continuous model x' = A x + B a_floor, a_seat = C x, with
    /// x = [z_seat, z_1, z_seat', z_1'] relative to the floor.
    pub fn state_space(&self) -> (Matrix4<f64>, Vector4<f64>, Vector4<f64>) {
        let (m0, m1) = (self.frame_mass_kg, self.moving_mass_kg);
        let (k1, c1) = (self.occupant_stiffness_n_m, self.occupant_damping_n_s_m);
        let (kc, cc) = (self.cushion_stiffness_n_m, self.cushion_damping_n_s_m);
        // m0 z_s'' = -kc z_s - cc z_s' + k1 (z_1 - z_s) + c1 (z_1' - z_s') - m0 a_floor
        // m1 z_1'' = -k1 (z_1 - z_s) - c1 (z_1' - z_s') - m1 a_floor
        let seat_row = [-(kc + k1) / m0, k1 / m0, -(cc + c1) / m0, c1 / m0];
        let body_row = [k1 / m1, -k1 / m1, c1 / m1, -c1 / m1];
        let a = Matrix4::new(
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
            seat_row[0],
            seat_row[1],
            seat_row[2],
            seat_row[3],
            body_row[0],
            body_row[1],
            body_row[2],
            body_row[3],
        );
        let b = Vector4::new(0.0, 0.0, -1.0, -1.0);
        // a_seat = a_floor + z_s'': the floor term cancels.
        let c = Vector4::new(seat_row[0], seat_row[1], seat_row[2], seat_row[3]);
        (a, b, c)
    }
}

/// The seat discretised at one sample rate.
#[derive(Clone, Debug)]
pub struct SeatFilter {
    phi: Matrix4<f64>,
    gamma0: Vector4<f64>,
    gamma1: Vector4<f64>,
    c: Vector4<f64>,
}

impl SeatFilter {
    /// The seat's filter at `rate_hz`, exact for an input linear between samples:
    /// exp([[A, B, 0], [0, 0, 1/h], [0, 0, 0]] h) holds Phi = e^(Ah) and the two input
    /// matrices of x[k+1] = Phi x[k] + G0 u[k] + G1 (u[k+1] - u[k]).
    pub fn new(seat: &Seat, rate_hz: f64) -> SeatFilter {
        let h = 1.0 / rate_hz;
        let (a, b, c) = seat.state_space();
        let mut m = DMatrix::<f64>::zeros(6, 6);
        for i in 0..4 {
            for j in 0..4 {
                m[(i, j)] = a[(i, j)] * h;
            }
            m[(i, 4)] = b[i] * h;
        }
        m[(4, 5)] = 1.0;
        let e = m.exp();
        SeatFilter {
            phi: Matrix4::from_fn(|i, j| e[(i, j)]),
            gamma0: Vector4::from_fn(|i, _| e[(i, 4)]),
            gamma1: Vector4::from_fn(|i, _| e[(i, 5)]),
            c,
        }
    }

    /// The seat-surface acceleration [m/s^2] from the floor's `a_floor` [m/s^2], the
    /// seat at rest relative to the floor at the first sample.
    pub fn apply(&self, a_floor: &[f64]) -> Vec<f64> {
        let mut x = Vector4::zeros();
        let mut out = Vec::with_capacity(a_floor.len());
        for (k, &u) in a_floor.iter().enumerate() {
            out.push(self.c.dot(&x));
            let next = a_floor.get(k + 1).copied().unwrap_or(u);
            x = self.phi * x + self.gamma0 * u + self.gamma1 * (next - u);
        }
        out
    }
}
