//! The three layouts of docs/model.md §11 as assemblies of bodies and elements.
//!
//! | layout | bodies (state order) | states |
//! |---|---|---|
//! | wheelset | wheelset 1 | 4 |
//! | bogie | wheelset 1 (x = +a, leading), wheelset 2 (x = −a), frame | 12 (14 with frame roll) |
//! | car | wheelsets 1–4 from the front, frame 1 (x = +l_b), frame 2, car body | 28 (34 with roll) |
//!
//! Elements, per side $s = ±1$ (right, left):
//! * **primary** (every layout): wheelset point $(0, s d, 0)$ to the frame's $(x_w, s d, −h_p)$
//!   (the track's, for the wheelset layout), stiffness $(K_{px}, K_{py}, K_{pz})$, damping
//!   $(C_{px}, C_{py}, C_{pz})$; $x_w = ±a$ is the wheelset's position on its frame, $h_p$ the
//!   primary's height above the frame's centre (frame roll only).
//! * **secondary** (bogie, car): frame point $(0, s d_s, −h_s)$ to the car body's
//!   $(x_b, s d_s, −h_c)$ (the track's, for a bogie), stiffness $(K_{sx}, K_{sy}, 0)$,
//!   damping $(C_{sx}, C_{sy}, 0)$; $x_b = ±l_b$, $h_s$ and $h_c$ the heights of the
//!   secondary above the frame's and the car body's centres.
//! * **secondary vertical** (when given): the same ends at $±d_v$, stiffness and damping along z.
//! * **yaw damper** (when given): the same ends at $±d_{yd}$, damping along x.
//! * any damper on series stiffness may follow a force–velocity curve ([`DamperCurves`])
//!   instead of its linear rate.
//! * **bump stops** (when given, docs/model.md §13): one per wheelset on the primary's lateral
//!   deflection and one per frame on the secondary's, free play $±δ_b$ then a stiff spring.
//!
//! Check (docs/model.md §11): for the wheelset layout the two primary elements give exactly
//! $F_s = −2K_{py}y − 2C_{py}\dot y$ and $M_s = −2K_{px}d^2ψ − 2C_{px}d^2\dot ψ$ of §7.

use super::vehicle::{AssemblyError, Attachment, Body, BodyKind, Element, Layout, Vehicle};
use super::{ForceVelocity, StopSpec, Wheelset};

/// The stiffness in series with each damper of a suspension (per side, N/m; docs/model.md §13):
/// `Some` makes that damper a Maxwell element with a stroke state; `None` attaches it rigidly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DamperSeries {
    /// in series with the lateral damper
    pub lateral: Option<f64>,
    /// in series with the longitudinal damper
    pub longitudinal: Option<f64>,
    /// in series with the vertical damper
    pub vertical: Option<f64>,
    /// in series with the yaw damper (secondary only)
    pub yaw: Option<f64>,
}

impl DamperSeries {
    /// Every damper rigidly attached (the elements of docs/model.md §11).
    pub const RIGID: Self = Self {
        lateral: None,
        longitudinal: None,
        vertical: None,
        yaw: None,
    };
}

/// The force–velocity curves of a suspension's dampers (docs/model.md §13), each on series
/// stiffness only, as [`DamperSeries`] lists them; `None`: linear, the section's damping. A
/// curve's slope at zero is that damping.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DamperCurves {
    /// the lateral damper's
    pub lateral: Option<ForceVelocity>,
    /// the longitudinal damper's
    pub longitudinal: Option<ForceVelocity>,
    /// the vertical damper's
    pub vertical: Option<ForceVelocity>,
    /// the yaw damper's (secondary only)
    pub yaw: Option<ForceVelocity>,
}

impl DamperCurves {
    /// Every damper linear.
    pub const LINEAR: Self = Self {
        lateral: None,
        longitudinal: None,
        vertical: None,
        yaw: None,
    };
}

/// The primary's values beyond docs/model.md §7 (per side), SI.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PrimaryVertical {
    /// vertical stiffness per side (N/m); acts only on a rolling frame
    pub stiffness: f64,
    /// vertical damping per side (N s/m)
    pub damping: f64,
    /// height of the primary above the frame's centre of mass (m; negative below)
    pub height: f64,
    /// the primary dampers' series stiffnesses (`yaw` unused)
    pub series: DamperSeries,
    /// the primary dampers' force–velocity curves (on series stiffness only)
    pub curves: DamperCurves,
    /// a lateral bump stop per wheelset, wheelset to frame (to the track for the wheelset
    /// layout), docs/model.md §13; `None`: none
    pub bump_stop: Option<StopSpec>,
}

/// A bogie frame, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameParams {
    /// mass (kg)
    pub mass: f64,
    /// yaw moment of inertia (kg m²)
    pub yaw_inertia: f64,
    /// roll moment of inertia (kg m²); `Some` adds the frame's roll
    pub roll_inertia: Option<f64>,
    /// half the wheelbase a (m): the wheelsets sit at x = ±a
    pub half_wheelbase: f64,
}

/// The secondary suspension per side, frame to car body, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Secondary {
    /// lateral stiffness per side (N/m)
    pub lateral_stiffness: f64,
    /// longitudinal stiffness per side (N/m)
    pub longitudinal_stiffness: f64,
    /// lateral damping per side (N s/m)
    pub lateral_damping: f64,
    /// longitudinal damping per side (N s/m)
    pub longitudinal_damping: f64,
    /// half the lateral spacing of the secondary springs d_s (m)
    pub half_spring_spacing: f64,
    /// longitudinal yaw-damper rate per side (N s/m); 0: none
    pub yaw_damping: f64,
    /// half the lateral spacing of the yaw dampers d_yd (m)
    pub yaw_damper_half_spacing: f64,
    /// vertical stiffness per side (N/m); acts only on rolling bodies
    pub vertical_stiffness: f64,
    /// vertical damping per side (N s/m)
    pub vertical_damping: f64,
    /// half the lateral spacing of the vertical springs d_v (m)
    pub vertical_half_spacing: f64,
    /// height of the secondary above the frame's centre of mass (m)
    pub height: f64,
    /// the secondary dampers' series stiffnesses
    pub series: DamperSeries,
    /// the secondary dampers' force–velocity curves (on series stiffness only); a yaw curve's
    /// slope at zero is `yaw_damping`
    pub curves: DamperCurves,
    /// a lateral bump stop per frame, frame to car body (to the track for a bogie),
    /// docs/model.md §13; `None`: none
    pub bump_stop: Option<StopSpec>,
}

/// The car body, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarBodyParams {
    /// mass (kg)
    pub mass: f64,
    /// yaw moment of inertia (kg m²)
    pub yaw_inertia: f64,
    /// roll moment of inertia (kg m²); `Some` adds the car body's roll
    pub roll_inertia: Option<f64>,
    /// half the distance between the bogie centres l_b (m)
    pub half_bogie_distance: f64,
    /// height of the secondary above the car body's centre of mass (m; negative below)
    pub secondary_height: f64,
}

/// Which layout, with the parameters it needs beyond the wheelset and its primary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VehicleSpec {
    /// the single wheelset on a track-fixed frame (docs/model.md §1–8)
    Wheelset,
    /// a bogie under a track-fixed car body
    Bogie {
        /// the frame
        frame: FrameParams,
        /// frame to track-fixed car body
        secondary: Secondary,
    },
    /// a whole car
    Car {
        /// each frame (both bogies are identical)
        frame: FrameParams,
        /// each bogie's secondary
        secondary: Secondary,
        /// the car body
        body: CarBodyParams,
    },
}

impl VehicleSpec {
    /// The layout.
    pub fn layout(&self) -> Layout {
        match self {
            VehicleSpec::Wheelset => Layout::Wheelset,
            VehicleSpec::Bogie { .. } => Layout::Bogie,
            VehicleSpec::Car { .. } => Layout::Car,
        }
    }

    /// Number of first-order states of this layout's bodies, $(q, \dot q)$; the dampers on
    /// series stiffness add their strokes ([`Vehicle::states`] counts them).
    pub fn states(&self) -> usize {
        let roll = |r: Option<f64>| 2 * usize::from(r.is_some());
        match self {
            VehicleSpec::Wheelset => 4,
            VehicleSpec::Bogie { frame, .. } => 12 + roll(frame.roll_inertia),
            VehicleSpec::Car { frame, body, .. } => {
                28 + 2 * roll(frame.roll_inertia) + roll(body.roll_inertia)
            }
        }
    }
}

fn body(name: String, kind: BodyKind, m: (f64, f64, Option<f64>), x: f64) -> Body {
    Body {
        name,
        kind,
        mass: m.0,
        yaw_inertia: m.1,
        roll_inertia: m.2,
        position_m: x,
        dof: 0,
    }
}

const SIDES: [(f64, &str); 2] = [(1.0, "right"), (-1.0, "left")];

fn at(body: Option<usize>, point: [f64; 3]) -> Attachment {
    Attachment { body, point }
}

/// Adds the primary elements of wheelset `w` at `x_on_frame` on `frame` (None: the track).
fn primary(
    out: &mut Vec<Element>,
    ws: &Wheelset,
    pv: &PrimaryVertical,
    w: (usize, &str),
    frame: Option<usize>,
    x_on_frame: f64,
) {
    let s = &ws.suspension;
    let d = s.half_spring_spacing;
    for (side, name) in SIDES {
        out.push(Element {
            name: format!("primary, {}, {name}", w.1),
            a: at(Some(w.0), [0.0, side * d, 0.0]),
            b: at(frame, [x_on_frame, side * d, -pv.height]),
            stiffness: [s.longitudinal_stiffness, s.lateral_stiffness, pv.stiffness],
            damping: [s.longitudinal_damping, s.lateral_damping, pv.damping],
            series_stiffness: [
                pv.series.longitudinal,
                pv.series.lateral,
                pv.series.vertical,
            ],
            force_velocity: [
                pv.curves.longitudinal,
                pv.curves.lateral,
                pv.curves.vertical,
            ],
            bump_stop: None,
        });
    }
    if let Some(stop) = pv.bump_stop {
        // one stop per wheelset on the lateral deflection of the springs above (the lateral
        // row does not depend on the side)
        out.push(Element {
            name: format!("primary bump stop, {}", w.1),
            a: at(Some(w.0), [0.0, 0.0, 0.0]),
            b: at(frame, [x_on_frame, 0.0, -pv.height]),
            stiffness: [0.0; 3],
            damping: [0.0; 3],
            series_stiffness: [None; 3],
            force_velocity: [None; 3],
            bump_stop: Some(stop),
        });
    }
}

/// Adds the secondary elements between `frame` and the car body (None: the track).
fn secondary(
    out: &mut Vec<Element>,
    sec: &Secondary,
    frame: (usize, &str),
    car: Option<usize>,
    car_point: (f64, f64),
) {
    let (xb, hc) = car_point;
    let series = &sec.series;
    type Laws = [Option<ForceVelocity>; 3];
    let mut add = |what: &str, d: f64, k: [f64; 3], c: [f64; 3], ks: [Option<f64>; 3], g: Laws| {
        if k.iter().chain(&c).all(|v| *v == 0.0) {
            return;
        }
        for (side, name) in SIDES {
            out.push(Element {
                name: format!("{what}, {}, {name}", frame.1),
                a: at(Some(frame.0), [0.0, side * d, -sec.height]),
                b: at(car, [xb, side * d, -hc]),
                stiffness: k,
                damping: c,
                series_stiffness: ks,
                force_velocity: g,
                bump_stop: None,
            });
        }
    };
    add(
        "secondary",
        sec.half_spring_spacing,
        [sec.longitudinal_stiffness, sec.lateral_stiffness, 0.0],
        [sec.longitudinal_damping, sec.lateral_damping, 0.0],
        [series.longitudinal, series.lateral, None],
        [sec.curves.longitudinal, sec.curves.lateral, None],
    );
    add(
        "secondary vertical",
        sec.vertical_half_spacing,
        [0.0, 0.0, sec.vertical_stiffness],
        [0.0, 0.0, sec.vertical_damping],
        [None, None, series.vertical],
        [None, None, sec.curves.vertical],
    );
    add(
        "yaw damper",
        sec.yaw_damper_half_spacing,
        [0.0; 3],
        [sec.yaw_damping, 0.0, 0.0],
        [series.yaw, None, None],
        [sec.curves.yaw, None, None],
    );
    if let Some(stop) = sec.bump_stop {
        // one stop per frame on the secondary springs' lateral deflection (roll lever arms
        // included; the lateral row does not depend on the side)
        out.push(Element {
            name: format!("secondary bump stop, {}", frame.1),
            a: at(Some(frame.0), [0.0, 0.0, -sec.height]),
            b: at(car, [xb, 0.0, -hc]),
            stiffness: [0.0; 3],
            damping: [0.0; 3],
            series_stiffness: [None; 3],
            force_velocity: [None; 3],
            bump_stop: Some(stop),
        });
    }
}

/// Builds the vehicle of `spec` around `contact` (the wheelset's mass, inertia, contact and
/// primary suspension per side) and the primary's vertical data `pv`.
pub fn build(
    spec: &VehicleSpec,
    contact: Wheelset,
    pv: &PrimaryVertical,
) -> Result<Vehicle, AssemblyError> {
    let p = contact.params;
    let ws_mass = (p.mass, p.yaw_inertia, None);
    let mut bodies = Vec::new();
    let mut elements = Vec::new();
    let frame_mass = |f: &FrameParams| (f.mass, f.yaw_inertia, f.roll_inertia);
    match spec {
        VehicleSpec::Wheelset => {
            bodies.push(body("wheelset 1".into(), BodyKind::Wheelset, ws_mass, 0.0));
            primary(&mut elements, &contact, pv, (0, "wheelset 1"), None, 0.0);
        }
        VehicleSpec::Bogie {
            frame,
            secondary: sec,
        } => {
            let a = frame.half_wheelbase;
            for (k, x) in [a, -a].into_iter().enumerate() {
                let name = format!("wheelset {}", k + 1);
                bodies.push(body(name, BodyKind::Wheelset, ws_mass, x));
            }
            bodies.push(body(
                "frame".into(),
                BodyKind::Frame,
                frame_mass(frame),
                0.0,
            ));
            for (k, x) in [a, -a].into_iter().enumerate() {
                let name = format!("wheelset {}", k + 1);
                primary(&mut elements, &contact, pv, (k, &name), Some(2), x);
            }
            secondary(&mut elements, sec, (2, "frame"), None, (0.0, 0.0));
        }
        VehicleSpec::Car {
            frame,
            secondary: sec,
            body: car,
        } => {
            let (a, lb) = (frame.half_wheelbase, car.half_bogie_distance);
            let wheelsets = [lb + a, lb - a, -lb + a, -lb - a];
            for (k, x) in wheelsets.into_iter().enumerate() {
                let name = format!("wheelset {}", k + 1);
                bodies.push(body(name, BodyKind::Wheelset, ws_mass, x));
            }
            for (k, x) in [lb, -lb].into_iter().enumerate() {
                let name = format!("frame {}", k + 1);
                bodies.push(body(name, BodyKind::Frame, frame_mass(frame), x));
            }
            let car_mass = (car.mass, car.yaw_inertia, car.roll_inertia);
            bodies.push(body("car body".into(), BodyKind::CarBody, car_mass, 0.0));
            for k in 0..4 {
                let name = format!("wheelset {}", k + 1);
                let x_on_frame = if k % 2 == 0 { a } else { -a };
                primary(
                    &mut elements,
                    &contact,
                    pv,
                    (k, &name),
                    Some(4 + k / 2),
                    x_on_frame,
                );
            }
            for (k, xb) in [lb, -lb].into_iter().enumerate() {
                let name = format!("frame {}", k + 1);
                let point = (xb, car.secondary_height);
                secondary(&mut elements, sec, (4 + k, &name), Some(6), point);
            }
        }
    }
    Vehicle::assemble(spec.layout(), bodies, elements, contact)
}

/// The single wheelset (docs/model.md §1–8) as a vehicle: the layout "wheelset" around `ws`, whose
/// primary has no vertical part.
pub fn single(ws: Wheelset) -> Result<Vehicle, AssemblyError> {
    build(&VehicleSpec::Wheelset, ws, &PrimaryVertical::default())
}
