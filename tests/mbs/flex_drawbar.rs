//! The trailer's drawbar (flex/drawbar.toml): the full FE model against closed-form beam
//! statics of its two clamped legs and the coupling head, the Craig-Bampton body with its
//! selected modes against the full FE model, the first held mode against a Rayleigh
//! estimate, and the modal damping from the file's sourced log decrement.

use std::f64::consts::PI;
use std::path::Path;

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};
use towride_mbs::flex::modes::{constrained_eigen, frequency_hz, static_solution};
use towride_mbs::flex::{FlexBody, ModalData, Options};

use super::flex_hitch::{modal_body_matrices, rows};

const FILE: &str = repo!("flex/drawbar.toml");

fn drawbar() -> FlexBody {
    FlexBody::load(
        Path::new(FILE),
        None,
        &Options::default(),
        &towride_mbs::input::Loader::new(),
    )
    .unwrap()
}

fn table() -> toml::Table {
    std::fs::read_to_string(FILE).unwrap().parse().unwrap()
}

fn num(v: &toml::Value) -> f64 {
    v.as_float().unwrap()
}

fn node(t: &toml::Table, name: &str) -> Vector3<f64> {
    let n = t["node"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"].as_str() == Some(name))
        .unwrap();
    let p: Vec<f64> = n["position_m"]
        .as_array()
        .unwrap()
        .iter()
        .map(num)
        .collect();
    Vector3::new(p[0], p[1], p[2])
}

/// A straight prismatic member's cross-section constants.
struct Member {
    /// Bending stiffness about the vertical-plane axis (height along z) and about the
    /// other transverse axis [N m^2], torsion G J [N m^2].
    ei_z_plane: f64,
    ei_other: f64,
    gj: f64,
    /// Axial stiffness E A [N].
    ea: f64,
    /// Shear stiffness G A_s in the vertical and the other transverse direction [N].
    gas_z: f64,
    gas_other: f64,
}

/// Tip flexibility (6 x 6: force, moment -> displacement, rotation) of a cantilever
/// from `root` to `tip` (clamped at the root), Timoshenko beam theory: with m(s) = M +
/// (L - s) d x F along the member, the tip rotation is int C m ds and the tip
/// displacement int C m x (L - s) d ds plus the shear deflection F_perp L / G A_s.
fn cantilever(root: Vector3<f64>, tip: Vector3<f64>, m: &Member) -> Matrix6<f64> {
    let l = (tip - root).norm();
    let d = (tip - root) / l;
    let up = Vector3::z();
    // Transverse axes: v in the vertical plane of the member, h horizontal.
    let h = up.cross(&d).normalize();
    let v = d.cross(&h);
    // Bending in the vertical plane turns about h.
    let c = d * d.transpose() / m.gj
        + h * h.transpose() / m.ei_z_plane
        + v * v.transpose() / m.ei_other;
    // Axial and shear strain, constant along the member.
    let shear =
        v * v.transpose() / m.gas_z + h * h.transpose() / m.gas_other + d * d.transpose() / m.ea;
    let mut g = Matrix6::zeros();
    for k in 0..6 {
        let mut load = Vector6::zeros();
        load[k] = 1.0;
        let f = Vector3::new(load[0], load[1], load[2]);
        let mm = Vector3::new(load[3], load[4], load[5]);
        let dxf = d.cross(&f);
        let rot = c * (mm * l + dxf * (l * l / 2.0));
        let disp = (c * mm * (l * l / 2.0)).cross(&d)
            + (c * dxf * (l * l * l / 3.0)).cross(&d)
            + shear * f * l;
        for i in 0..3 {
            g[(i, k)] = disp[i];
            g[(3 + i, k)] = rot[i];
        }
    }
    g
}

/// The drawbar in closed form: its members' constants and the apex flexibility.
struct ClosedForm {
    leg: Member,
    head: Member,
    apex: Vector3<f64>,
    ball: Vector3<f64>,
    roots: [Vector3<f64>; 2],
    /// Apex flexibility of the two legs clamped at their front bolts.
    flex_apex: Matrix6<f64>,
    /// Mass per length of a leg and of the head [kg/m].
    rho_a_leg: f64,
    rho_a_head: f64,
}

impl ClosedForm {
    fn new() -> ClosedForm {
        let t = table();
        let mat = &t["material"][0];
        let (e, nu) = (num(&mat["youngs_modulus_pa"]), num(&mat["poissons_ratio"]));
        let rho = num(&mat["density_kg_m3"]);
        let g = e / (2.0 * (1.0 + nu));
        let secs = t["section"].as_array().unwrap();
        let leg = &secs[0];
        let (b, h, w) = (
            num(&leg["width_m"]),
            num(&leg["height_m"]),
            num(&leg["wall_m"]),
        );
        let (bi, hi) = (b - 2.0 * w, h - 2.0 * w);
        let area = b * h - bi * hi;
        // Thin-walled closed section: Bredt's J (Roark table 10.7 case 16).
        let am = (b - w) * (h - w);
        let j = 4.0 * am * am * w / (2.0 * (b + h - 2.0 * w));
        let leg_m = Member {
            ei_z_plane: e * (b * h.powi(3) - bi * hi.powi(3)) / 12.0,
            ei_other: e * (h * b.powi(3) - hi * bi.powi(3)) / 12.0,
            gj: g * j,
            ea: e * area,
            // Web areas carry the shear (EN 1993-1-1 6.2.6(3)).
            gas_z: g * area * h / (b + h),
            gas_other: g * area * b / (b + h),
        };
        let dia = num(&secs[1]["diameter_m"]);
        let ih = PI * dia.powi(4) / 64.0;
        // Cowper's (1966) shear coefficient of a solid circle.
        let kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
        let ah = PI * dia * dia / 4.0;
        let head = Member {
            ei_z_plane: e * ih,
            ei_other: e * ih,
            gj: g * 2.0 * ih,
            ea: e * ah,
            gas_z: g * kappa * ah,
            gas_other: g * kappa * ah,
        };
        let apex = node(&t, "apex");
        let roots = [node(&t, "left_bolt_front"), node(&t, "right_bolt_front")];
        let mut k_apex = Matrix6::zeros();
        for r in roots {
            k_apex += cantilever(r, apex, &leg_m).try_inverse().unwrap();
        }
        ClosedForm {
            leg: leg_m,
            head,
            apex,
            ball: node(&t, "ball"),
            roots,
            flex_apex: k_apex.try_inverse().unwrap(),
            rho_a_leg: rho * area,
            rho_a_head: rho * ah,
        }
    }

    /// Apex displacement and rotation under the ball force `f`.
    fn apex_motion(&self, f: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let mut at_apex = Vector6::zeros();
        at_apex.fixed_rows_mut::<3>(0).copy_from(&f);
        at_apex
            .fixed_rows_mut::<3>(3)
            .copy_from(&(self.ball - self.apex).cross(&f));
        let u = self.flex_apex * at_apex;
        (u.fixed_rows::<3>(0).into(), u.fixed_rows::<3>(3).into())
    }

    /// Displacement of a point `p` of the head (on the apex-ball line) under the ball
    /// force `f`: the apex's motion carried to p, plus the head between apex and p bent
    /// by the force and its moment about p.
    fn head_point(&self, p: Vector3<f64>, f: Vector3<f64>) -> Vector3<f64> {
        let (ua, ta) = self.apex_motion(f);
        let mut u = ua + ta.cross(&(p - self.apex));
        if (p - self.apex).norm() > 1e-12 {
            let load = Vector6::new(f[0], f[1], f[2], 0.0, 0.0, 0.0);
            let m = (self.ball - p).cross(&f);
            let mut l = load;
            l.fixed_rows_mut::<3>(3).copy_from(&m);
            u += (cantilever(self.apex, p, &self.head) * l).fixed_rows::<3>(0);
        }
        u
    }

    /// Displacement of a point `p` of leg `k` under the ball force `f`: the leg is a
    /// cantilever from its root, loaded at the apex by the share its stiffness carries.
    fn leg_point(&self, k: usize, p: Vector3<f64>, f: Vector3<f64>) -> Vector3<f64> {
        let root = self.roots[k];
        if (p - root).norm() < 1e-12 {
            return Vector3::zeros();
        }
        let (ua, ta) = self.apex_motion(f);
        let mut ut = Vector6::zeros();
        ut.fixed_rows_mut::<3>(0).copy_from(&ua);
        ut.fixed_rows_mut::<3>(3).copy_from(&ta);
        // The apex load this leg carries, moved from the apex to p.
        let load = cantilever(root, self.apex, &self.leg)
            .try_inverse()
            .unwrap()
            * ut;
        let (fl, ml) = (
            Vector3::new(load[0], load[1], load[2]),
            Vector3::new(load[3], load[4], load[5]),
        );
        let at_p = ml + (self.apex - p).cross(&fl);
        let l = Vector6::new(fl[0], fl[1], fl[2], at_p[0], at_p[1], at_p[2]);
        (cantilever(root, p, &self.leg) * l)
            .fixed_rows::<3>(0)
            .into()
    }

    /// 3 x 3 ball compliance.
    fn ball_compliance(&self) -> Matrix3<f64> {
        let mut out = Matrix3::zeros();
        for d in 0..3 {
            out.set_column(d, &self.head_point(self.ball, Vector3::ith(d, 1.0)));
        }
        out
    }

    /// Rayleigh's quotient with the static deflection under a unit ball force along `d`
    /// as the shape: omega^2 = f . u_ball / int rho A |u|^2 ds (midpoint rule).
    fn rayleigh_hz(&self, d: usize) -> f64 {
        let f = Vector3::ith(d, 1.0);
        let n = 400;
        let mut ke = 0.0;
        let lh = (self.ball - self.apex).norm();
        for i in 0..n {
            let s = (i as f64 + 0.5) / n as f64;
            let u = self.head_point(self.apex + (self.ball - self.apex) * s, f);
            ke += self.rho_a_head * lh / n as f64 * u.norm_squared();
            for k in 0..2 {
                let ll = (self.apex - self.roots[k]).norm();
                let u = self.leg_point(k, self.roots[k] + (self.apex - self.roots[k]) * s, f);
                ke += self.rho_a_leg * ll / n as f64 * u.norm_squared();
            }
        }
        let work = f.dot(&self.head_point(self.ball, f));
        (work / ke).sqrt() / (2.0 * PI)
    }
}

/// DOFs of the frame attachments (the interface nodes carry the bolts' spiders).
fn frame_dofs(b: &FlexBody) -> Vec<usize> {
    ["frame_left", "frame_right"]
        .iter()
        .flat_map(|n| b.assembly.dofs(b.mesh.interface(n).unwrap().node))
        .collect()
}

/// Ball compliance of the full FE model held at the frame.
fn full_ball_compliance(b: &FlexBody) -> Matrix3<f64> {
    let held = frame_dofs(b);
    let ball = b.assembly.dofs(b.mesh.interface("ball").unwrap().node);
    let mut out = Matrix3::zeros();
    for d in 0..3 {
        let mut f = vec![0.0; b.assembly.n_dof];
        f[ball[d]] = 1.0;
        let u = static_solution(b.assembly.k.as_ref(), &held, &f).unwrap();
        for i in 0..3 {
            out[(i, d)] = u[ball[i]];
        }
    }
    out
}

/// Constraint rows holding the modal body at its frame attachments.
fn frame_rows(md: &ModalData) -> DMatrix<f64> {
    DMatrix::from_rows(
        &[rows(md, "frame_left"), rows(md, "frame_right")]
            .iter()
            .flat_map(|g| g.row_iter().map(|r| r.into_owned()).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
    )
}

/// Ball deflection along `d` of the modal body held at the frame, unit load along `d`.
fn modal_ball_compliance(md: &ModalData, d: usize) -> f64 {
    let (_, k) = modal_body_matrices(md);
    let c = frame_rows(md);
    let gb = rows(md, "ball");
    let (nz, nc) = (k.nrows(), c.nrows());
    let mut a = DMatrix::zeros(nz + nc, nz + nc);
    a.view_mut((0, 0), (nz, nz)).copy_from(&k);
    a.view_mut((nz, 0), (nc, nz)).copy_from(&c);
    a.view_mut((0, nz), (nz, nc)).copy_from(&c.transpose());
    let mut rhs = DVector::zeros(nz + nc);
    rhs.rows_mut(0, nz).copy_from(&gb.row(d).transpose());
    let z = a.lu().solve(&rhs).unwrap();
    (gb.row(d) * z.rows(0, nz))[(0, 0)]
}

#[test]
fn full_fe_drawbar_deflects_as_closed_form_beam_statics() {
    let b = drawbar();
    let fe = full_ball_compliance(&b);
    let cf = ClosedForm::new().ball_compliance();
    for d in 0..3 {
        println!(
            "ball compliance along {d}: full FE {:.6e} m/N, closed form {:.6e} m/N",
            fe[(d, d)],
            cf[(d, d)]
        );
    }
    // Both are exact beam statics (the element is exact for a prismatic member).
    assert!((fe - cf).norm() < 1e-6 * cf.norm(), "{fe} vs {cf}");
}

#[test]
fn modal_drawbar_with_its_selected_modes_is_as_stiff_as_the_full_model() {
    let b = drawbar();
    let fe = full_ball_compliance(&b);
    let kept = b.modal.selected();
    for d in 0..3 {
        let all = modal_ball_compliance(&b.modal, d);
        let sel = modal_ball_compliance(&kept, d);
        println!(
            "ball stiffness along {d}: full FE {:.4e} N/m, modal (all {}) {:.4e} N/m, modal (selected {}) {:.4e} N/m ({:+.2} %)",
            1.0 / fe[(d, d)],
            b.modal.modes.len(),
            1.0 / all,
            kept.modes.len(),
            1.0 / sel,
            100.0 * (fe[(d, d)] / sel - 1.0)
        );
        assert!((all / fe[(d, d)] - 1.0).abs() < 1e-6);
        assert!((sel / fe[(d, d)] - 1.0).abs() < 0.01);
    }
}

#[test]
fn first_held_nose_mode_matches_a_rayleigh_estimate() {
    let b = drawbar();
    let full = constrained_eigen(
        b.assembly.k.as_ref(),
        b.assembly.m.as_ref(),
        &frame_dofs(&b),
    )
    .unwrap();
    // Rayleigh's estimate is an upper bound, close for the fundamental; the bolts'
    // part of the legs (held) and rotary inertia are left out.
    let f_est = ClosedForm::new().rayleigh_hz(2);
    // The held mode whose shape moves the ball most vertically.
    let ball_z = b.assembly.dofs(b.mesh.interface("ball").unwrap().node)[2];
    let k = (0..6)
        .max_by(|&i, &j| {
            full.vectors[(ball_z, i)]
                .abs()
                .total_cmp(&full.vectors[(ball_z, j)].abs())
        })
        .unwrap();
    let f = frequency_hz(full.omega2[k]);
    println!(
        "held at the frame: modes {:?} Hz; nose bounce mode {f:.1} Hz, Rayleigh {f_est:.1} Hz",
        full.omega2[..6]
            .iter()
            .map(|&w| frequency_hz(w))
            .collect::<Vec<_>>()
    );
    assert!((f / f_est - 1.0).abs() < 0.02);
}

#[test]
fn modal_damping_is_the_files_log_decrement() {
    // EN 1991-1-4 Table F.2, ordinary bolts: delta = 0.05, zeta = delta / (2 pi).
    let want = 0.05 / (2.0 * PI);
    for m in &drawbar().modal.modes {
        assert!(
            (m.damping_ratio / want - 1.0).abs() < 0.01,
            "{}",
            m.damping_ratio
        );
    }
}
