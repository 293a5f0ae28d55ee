//! Preset and its parts: the stone, the launch, the physics and the water (design.md §6, the preset
//! contract), with the range checks that keep every run finite.
//!
//! Units are SI; angles are degrees here (the preset is an edge of the program) and radians everywhere
//! inside `sim`. Every field has a default, so a preset may name only what it changes.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Errors from validating a preset: which field, what it holds and what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("field `{field}`: {message}")]
pub struct ParamError {
    /// Dotted path of the field, e.g. `stone.mass`.
    pub field: String,
    /// What was wrong and what was expected.
    pub message: String,
}

impl ParamError {
    /// The error for `field` (a dotted path such as `stone.mass`), saying what was wrong and what
    /// was expected.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            message: message.into(),
        }
    }
}

/// One throw: everything a run needs.
///
/// A field a preset does not name takes the value of its schema's base (design.md §3): in a
/// `version: 1` file the model before the fidelity work ([`Preset::version_1`]), in a
/// `version: 2` file the shipped default ([`Preset::default`], `assets/presets/default.ron` as
/// compiled in). A parse states its schema with `with_schema`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default = "Preset::omitted", deny_unknown_fields)]
pub struct Preset {
    /// The schema: 1 (omitted fields: the model before the fidelity work) or 2 (omitted fields:
    /// the shipped default).
    pub version: u32,
    /// The throw's name, as the summary reports it.
    pub name: String,
    /// The stone's shape, mass and mesh.
    pub stone: StoneParams,
    /// The throw's initial position, velocity, attitude and spin.
    pub launch: Launch,
    /// The physical constants, the force law and the numerics.
    pub physics: Physics,
    /// The column-and-pipe water.
    pub water: WaterParams,
}

/// The shipped default throw as compiled in: the base of a `version: 2` preset's omitted fields and
/// [`Preset::default`]. It is written as `version: 2` and names every field where the two schemas
/// differ, so it reads the same with either base; it is parsed with version 1's (its own omitted
/// fields cannot come from itself).
pub(crate) const SHIPPED_DEFAULT_RON: &str = include_str!("../../../../assets/presets/default.ron");

/// The newest preset schema: omitted fields mean the shipped default.
pub(crate) const LATEST_SCHEMA: u32 = 2;

thread_local! {
    /// The schema whose base fills the omitted fields of the preset being parsed on this thread.
    static OMITTED_FROM: std::cell::Cell<u32> = const { std::cell::Cell::new(1) };
}

/// Runs `parse` with omitted preset fields taken from schema `version`'s base (1: the model before
/// the fidelity work; 2: the shipped default); the previous schema is restored afterwards, even if
/// `parse` unwinds.
pub(crate) fn with_schema<T>(version: u32, parse: impl FnOnce() -> T) -> T {
    struct Restore(u32);
    impl Drop for Restore {
        fn drop(&mut self) {
            OMITTED_FROM.with(|s| s.set(self.0));
        }
    }
    let _restore = Restore(OMITTED_FROM.with(|s| s.replace(version)));
    parse()
}

impl Default for Preset {
    /// The shipped default throw (`assets/presets/default.ron` as compiled in): one definition,
    /// the one the app opens with.
    fn default() -> Self {
        Self::shipped_default().clone()
    }
}

impl Preset {
    /// The compiled-in default, parsed once. The file is checked by the tests
    /// (`the_compiled_in_default_is_valid`), so the parse cannot fail at run time.
    fn shipped_default() -> &'static Preset {
        static SHIPPED: std::sync::OnceLock<Preset> = std::sync::OnceLock::new();
        SHIPPED.get_or_init(|| {
            match with_schema(1, || {
                ron::Options::default().from_str::<Preset>(SHIPPED_DEFAULT_RON)
            }) {
                Ok(preset) => preset,
                Err(e) => panic!("the compiled-in default preset does not parse: {e}"),
            }
        })
    }

    /// The base of the preset being parsed (see [`with_schema`]).
    fn omitted() -> Self {
        if OMITTED_FROM.with(|s| s.get()) >= 2 {
            Self::default()
        } else {
            Self::version_1()
        }
    }

    /// What a `version: 1` preset's omitted fields mean: the model before the fidelity work (the
    /// paper's faceted, locked stone without buoyancy, air or memory) and its 10 m/s throw. The
    /// tests and studies written against it keep using it.
    pub fn version_1() -> Self {
        Self {
            version: 1,
            name: "Default throw".to_owned(),
            stone: StoneParams::version_1(),
            launch: Launch::version_1(),
            physics: Physics::version_1(),
            water: WaterParams::version_1(),
        }
    }
}

/// The stone's shape (design.md §4). Body frame: symmetry axis = body z; a plate's length along body x.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Shape {
    /// Flat-faced cylinder: the literature's disc.
    Disk {
        /// m
        radius: f64,
        /// Height of the cylinder along the axis (m).
        thickness: f64,
    },
    /// Ellipsoid of revolution with semi-axes (radius, radius, thickness/2): the paper's stone.
    Lens {
        /// Equatorial semi-axis (m).
        radius: f64,
        /// Twice the polar semi-axis: the thickness along the axis (m).
        thickness: f64,
    },
    /// Thin box: Bocquet's square plate.
    Plate {
        /// Along body x (m).
        length: f64,
        /// Along body y (m).
        width: f64,
        /// Along body z (m).
        thickness: f64,
    },
}

impl Shape {
    /// A body of revolution (disk or lens): its mesh is rings about its axis, its inertia
    /// axisymmetric; a plate is not.
    pub fn is_revolution(&self) -> bool {
        matches!(self, Shape::Disk { .. } | Shape::Lens { .. })
    }

    /// Largest horizontal half-extent of the stone (m): the radius, or half the plate's diagonal.
    pub fn half_extent(&self) -> f64 {
        match *self {
            Shape::Disk { radius, .. } | Shape::Lens { radius, .. } => radius,
            Shape::Plate { length, width, .. } => 0.5 * (length * length + width * width).sqrt(),
        }
    }

    /// Thickness along the axis (body z) (m), whatever the shape.
    pub fn thickness(&self) -> f64 {
        match *self {
            Shape::Disk { thickness, .. }
            | Shape::Lens { thickness, .. }
            | Shape::Plate { thickness, .. } => thickness,
        }
    }

    /// The variant's name as a preset writes it: `Disk`, `Lens` or `Plate`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Shape::Disk { .. } => "Disk",
            Shape::Lens { .. } => "Lens",
            Shape::Plate { .. } => "Plate",
        }
    }
}

/// The preset's stone (`stone`): shape, mass, mesh resolution and quadrature.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default = "StoneParams::omitted", deny_unknown_fields)]
pub struct StoneParams {
    /// Shape and dimensions.
    pub shape: Shape,
    /// kg
    pub mass: f64,
    /// Rim resolution of the mesh.
    pub segments: u32,
    /// A lens's latitude bands from pole to pole (uniform in the polar angle); `None`: half the
    /// segments (at least 4), the mesh every preset had before this field. Ignored for a disk or
    /// a plate. Written `bands: 16` (plain, like the law's coefficients).
    #[serde(
        deserialize_with = "de_plain_option",
        serialize_with = "ser_plain_option",
        skip_serializing_if = "Option::is_none"
    )]
    pub bands: Option<u32>,
    /// How the water's forces are summed over a lens (numerics: the same law either way).
    /// Omitted in a `version: 1` preset: `Faces`, every wetted triangle of the mesh (the paper).
    /// Always saved, since a `version: 2` preset that omits it has the shipped lens's `Smooth`.
    pub quadrature: Quadrature,
}

/// Where the force law is evaluated (`stone.quadrature`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum Quadrature {
    /// At the wetted centroid of every wetted triangle of the mesh (paper eqs. 24–26).
    #[default]
    Faces,
    /// On the smooth ellipsoid of a lens (`src/sim/smooth.rs`): a Gauss–Legendre rule with
    /// `meridian` nodes along the wet latitudes; around each latitude the waterline is exact and
    /// the pressure integrated in closed form, and `around` Gauss nodes on each piece of the arc
    /// take the friction; its axial spin smooth. A lens over flat water: on wavy water, and for a
    /// disk or a plate, the mesh's faces carry the load.
    Smooth {
        /// Gauss–Legendre nodes along the wet latitudes (2–64).
        meridian: u32,
        /// Gauss nodes on each piece of a latitude's wet arc, for the friction (2–64).
        around: u32,
    },
}

impl Quadrature {
    /// Whether this is `Faces` (the mesh's triangles, the paper's sum).
    pub fn is_faces(&self) -> bool {
        *self == Quadrature::Faces
    }
}

impl StoneParams {
    /// The base of the preset being parsed (see [`with_schema`]).
    fn omitted() -> Self {
        Preset::omitted().stone
    }

    /// A `version: 1` preset's omitted stone (see [`Preset::version_1`]).
    pub fn version_1() -> Self {
        // A flat river stone: 5 cm radius, 1 cm thick, 100 g.
        Self {
            shape: Shape::Lens {
                radius: 0.05,
                thickness: 0.012,
            },
            mass: 0.1,
            segments: 32,
            bands: None,
            quadrature: Quadrature::Faces,
        }
    }
}

/// Attitude as three named angles in degrees (design.md §3):
/// orientation = Rz(heading) · Rx(bank) · Ry(−tilt).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Attitude {
    /// Pitch about body y, the leading (+x) edge up (°): the Ry(−tilt).
    pub tilt_deg: f64,
    /// Roll about the horizontal heading direction (°): the Rx(bank).
    pub bank_deg: f64,
    /// Yaw about the vertical, degrees from +x towards +y: the Rz(heading).
    pub heading_deg: f64,
}

impl Default for Attitude {
    fn default() -> Self {
        Self {
            tilt_deg: 20.0,
            bank_deg: 0.0,
            heading_deg: 0.0,
        }
    }
}

/// The throw's initial state (`launch`); positions and velocities in the world frame (z up, the
/// water at rest at z = 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default = "Launch::omitted", deny_unknown_fields)]
pub struct Launch {
    /// m, centre of mass.
    pub position: [f64; 3],
    /// m/s.
    pub velocity: [f64; 3],
    /// The stone's orientation at release.
    pub attitude: Attitude,
    /// rad/s about the stone's axis.
    pub spin: f64,
    /// rad/s, world frame, added to the spin (wobble).
    pub angular_velocity: [f64; 3],
}

impl Launch {
    /// The base of the preset being parsed (see [`with_schema`]).
    fn omitted() -> Self {
        Preset::omitted().launch
    }

    /// A `version: 1` preset's omitted launch (see [`Preset::version_1`]).
    pub fn version_1() -> Self {
        Self {
            position: [0.0, 0.0, 0.3],
            velocity: [10.0, 0.0, -1.0],
            attitude: Attitude::default(),
            spin: 60.0,
            angular_velocity: [0.0; 3],
        }
    }
}

/// The water's force law on a wetted face (`physics.force_law`; `law.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ForceLaw {
    /// Eqs. 11–24 as printed: ½ C_l ρ v_n² S normal, ½ C_f ρ |V_t|² S tangential.
    Paper,
    /// Bocquet 2003 eqs. 1–3: ½ C_l ρ U² S and ½ C_f ρ U² S.
    Bocquet,
    /// Rosellini et al. 2005 eq. 4.2: C_L ρ U max(0, v_n) S normal; friction as the paper.
    Rosellini,
}

impl ForceLaw {
    /// Every law, in the order the app and the studies list them.
    pub const ALL: [ForceLaw; 3] = [ForceLaw::Rosellini, ForceLaw::Paper, ForceLaw::Bocquet];

    /// The law's default (C_l, C_f) (design.md §4).
    pub fn default_coefficients(self) -> (f64, f64) {
        match self {
            ForceLaw::Rosellini => (0.5, 0.005),
            ForceLaw::Paper => (1.4, 0.005),
            ForceLaw::Bocquet => (1.0, 1.0),
        }
    }
}

/// How the stone's motion is stepped (`physics.integrator`; `integrate.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Integrator {
    /// Eqs. 30–38: forces at the start, velocity by Euler, position by the trapezoid.
    Paper,
    /// Semi-implicit Euler: velocity first, then position with the new velocity (symplectic).
    SymplecticEuler,
    /// Classical fourth-order Runge–Kutta (four force evaluations a step).
    Rk4,
    /// Exact flight, contact entry by root finding, error-controlled steps in contact.
    Adaptive,
}

impl Integrator {
    /// Every integrator, in the order the app and the studies list them.
    pub const ALL: [Integrator; 4] = [
        Integrator::Paper,
        Integrator::SymplecticEuler,
        Integrator::Rk4,
        Integrator::Adaptive,
    ];
}

/// Whether the stone's attitude may change (`physics.rotation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Rotation {
    /// Attitude held fixed (the paper; the high-spin limit).
    Locked,
    /// Free rigid body: torque, spin, gyroscope.
    Free,
}

/// Every value `physics.pressure_centre` ever took. The field is folded away: each wetted face's
/// pressure acts at that face's wetted centroid (the paper's eqs. 25–26), the only model left, so
/// `Faces`, which every preset saved before wrote, is read and ignored; Savitsky's planing centre
/// (`Planing(f)`) is retired (docs/studies/retired.md).
#[derive(Deserialize)]
enum PressureCentreName {
    Faces,
    Planing(#[allow(dead_code)] f64),
}

fn read_pressure_centre<'de, D: Deserializer<'de>>(d: D) -> Result<RetiredSettings, D::Error> {
    match PressureCentreName::deserialize(d)? {
        PressureCentreName::Faces => Ok(RetiredSettings),
        PressureCentreName::Planing(_) => Err(serde::de::Error::custom(Retired {
            field: "physics.pressure_centre",
            value: "Planing",
            why: "Savitsky's planing centre moved the skip count by at most one and no shipped \
                  preset used it; leave the field out (each face's pressure acts at its wetted centroid)",
        })),
    }
}

/// A preset value that is retired (issue 40): its question is answered and no shipped preset used
/// it. Reading it fails with this one message, which names the field and where its results are.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "`{field}: {value}` is retired: {why}; its results, and the git tag that still runs it, are \
     in docs/studies/retired.md"
)]
pub struct Retired {
    /// Dotted path of the field, e.g. `physics.axial_spin`.
    pub field: &'static str,
    /// The retired value as a preset writes it.
    pub value: &'static str,
    /// Why it was retired and what to write instead.
    pub why: &'static str,
}

/// How a wetted face that recedes from the water is loaded when `ventilated` is false (physics.md
/// §7.1–7.2; issue 11). With `ventilated: true` receding faces carry nothing and this has no effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PressureSign {
    /// The paper's eqs. 17–19 as printed: every wetted face is pushed along −N, so a receding face is
    /// pushed the way it already moves and the water does work on the stone (energy from nowhere).
    AsPrinted,
    /// The energy-consistent reading: each face's pressure opposes its own normal velocity
    /// (F_n = −p(|v_n|) sign(v_n) N), so every face's force does negative work (no energy gained).
    OpposesMotion,
}

/// What the per-face pressure sees of the spin about a body of revolution's own axis.
/// (`Smooth`, the Résal law on a mesh that turns with the spin, is retired:
/// docs/studies/retired.md.)
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "AxialSpinName")]
pub enum AxialSpin {
    /// The faceted mesh as it is: the spin's velocity ω_s a × r has a normal component on facets
    /// that are not exactly tangent to the circles of the revolution (at 50 rev/s it paddles the
    /// water with a few m/s of spurious normal velocity near the rim).
    Faceted,
    /// The smooth body of revolution the mesh stands for: a surface of revolution spinning about
    /// its axis moves only along itself, so the axial spin adds nothing to any face's normal
    /// velocity (it still drags tangentially through friction); and under free rotation the mesh
    /// meets the water in a Résal frame (the frame of gyroscope theory that follows the symmetry
    /// axis but not the spin about it): its azimuth is held to the flow, the mesh's azimuth 0 (a
    /// column of vertices) on the velocity's component in the stone's plane. The smooth body's
    /// forces do not depend on that azimuth, but the faceted mesh's do: turning with the spin, its
    /// facets would sweep past the waterline spin × segments times a second (900 Hz at 14 rev/s
    /// and 64 segments), a ripple of the force that is the mesh's and not the body's, and that the
    /// error control of `Adaptive` resolves with small steps. The stone's orientation, spin and
    /// rendering are unchanged. Plates are not bodies of revolution: no effect.
    Resal,
}

/// Every value `physics.axial_spin` ever took, the retired one included.
#[derive(Deserialize)]
enum AxialSpinName {
    Faceted,
    Smooth,
    Resal,
}

impl TryFrom<AxialSpinName> for AxialSpin {
    type Error = Retired;
    fn try_from(name: AxialSpinName) -> Result<Self, Retired> {
        match name {
            AxialSpinName::Faceted => Ok(Self::Faceted),
            AxialSpinName::Resal => Ok(Self::Resal),
            AxialSpinName::Smooth => Err(Retired {
                field: "physics.axial_spin",
                value: "Smooth",
                why: "Resal is the same smooth law with the mesh held to the flow, the same \
                      forces without the facets' ripple; write Resal",
            }),
        }
    }
}

impl AxialSpin {
    /// Whether the pressure sees the spin about the axis (`Faceted`) or not.
    pub fn is_smooth(self) -> bool {
        self != AxialSpin::Faceted
    }
}

/// Which wetted faces carry the hydrostatic pressure ρ g d when `buoyancy` is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Hydrostatic {
    /// Only the faces that carry the dynamic pressure (with `ventilated: true`, those advancing into
    /// the water): a receding face loses its hydrostatic load too, so a submerged stone feels the
    /// depth of its advancing side only, not Archimedes' ρ g V, and every face whose normal velocity
    /// changes sign switches a finite force (finding A1, docs/reliability.md). Today's behaviour.
    LoadedFaces,
    /// Every wetted face (Archimedes: over the wetted surface the pressures ρ g d sum to ρ g times
    /// the submerged volume, whatever the faces' motion). Ventilation (the flow leaving a receding
    /// face, Rosellini et al. 2005) then removes the dynamic pressure and friction only.
    WettedFaces,
}

/// The preset's physics (`physics`): constants, the water's force law and its options, the air,
/// and the numerics of the stone's motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default = "Physics::omitted", deny_unknown_fields)]
pub struct Physics {
    /// m/s²
    pub gravity: f64,
    /// kg/m³
    pub water_density: f64,
    /// The water's force law on a wetted face.
    pub force_law: ForceLaw,
    /// C_l. Omitted: the law's default.
    #[serde(
        deserialize_with = "de_plain_option",
        serialize_with = "ser_plain_option",
        skip_serializing_if = "Option::is_none"
    )]
    pub lift_coefficient: Option<f64>,
    #[serde(
        deserialize_with = "de_plain_option",
        serialize_with = "ser_plain_option",
        skip_serializing_if = "Option::is_none"
    )]
    /// C_f. Omitted: the law's default.
    pub friction_coefficient: Option<f64>,
    /// Pressure and friction only on faces advancing into the water.
    pub ventilated: bool,
    /// How the stone's motion is stepped.
    pub integrator: Integrator,
    /// Adaptive's relative error per step.
    pub tolerance: f64,
    /// Whether the attitude is held (the paper) or free.
    pub rotation: Rotation,
    /// `pressure_centre: Faces`, which presets saved before the field was folded away write: read
    /// and ignored, never written (`Planing` fails as retired).
    #[serde(
        default,
        rename = "pressure_centre",
        skip_serializing,
        deserialize_with = "read_pressure_centre"
    )]
    pub retired_pressure_centre: RetiredSettings,
    /// How a receding wetted face is loaded when not ventilated.
    pub pressure_sign: PressureSign,
    /// Whether the axial spin of a body of revolution is felt as normal velocity by its facets.
    pub axial_spin: AxialSpin,
    /// Hydrostatic pressure ρ g d on the loaded faces (Archimedes; d the wetted centroid's depth).
    pub buoyancy: bool,
    /// Which wetted faces carry the hydrostatic pressure (with `buoyancy`).
    pub hydrostatic: Hydrostatic,
    /// The air's lift, drag and pitching moment in flight (`air.rs`); `None`: a vacuum between
    /// contacts (the paper's parabola).
    pub air: Option<AirParams>,
    /// s: the tick (fixed step; Adaptive's upper bound).
    pub dt: f64,
    /// s
    pub max_time: f64,
    /// Numerics, not physics: `Adaptive`'s contact steps may end past the tick's end when no water
    /// takes the stone's loads (water off, or a headless run that leaves it at rest), so the tick
    /// no longer caps the step; the stone then runs up to one step ahead of the tick. Omitted:
    /// false in a `version: 1` preset, every step inside its tick (docs/studies/kernel.md, "What
    /// sets the glide's step"). Always saved, since the shipped default sets it.
    pub steps_across_ticks: bool,
    /// The wetted-extent memory (`memory.rs`): the waterline the faces are clipped against lags
    /// the geometric one with τ = lag · L/|U|. `None`: the quasi-steady contact of the paper (and
    /// of every `version: 1` preset that does not name it). Always saved, `None` included, since a
    /// `version: 2` preset that omits it has the shipped default's memory.
    pub wetted_memory: Option<MemoryParams>,
}

/// The preset's air (`physics.air`; the model in `air.rs`): density and the disc's coefficients (per radian).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AirParams {
    /// kg/m³ (dry air at 20 °C, sea level)
    pub density: f64,
    /// C_Lα (1/rad)
    pub lift_slope: f64,
    /// C_D0
    pub drag_zero: f64,
    /// C_Dα (1/rad²)
    pub drag_slope: f64,
    /// C_Mα (1/rad), about the centre, positive nose up for α > 0.
    pub moment_slope: f64,
}

impl Default for AirParams {
    fn default() -> Self {
        Self {
            density: 1.204,
            lift_slope: 1.91,
            drag_zero: 0.18,
            drag_slope: 0.69,
            moment_slope: 0.43,
        }
    }
}

/// The length L of the memory's lag τ = lag · L/|U| (`memory.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum LagLength {
    /// The geometric streamwise wetted length s_g: the transit time of the water under the patch
    /// (the Wagner-strip derivation, docs/studies/wagner_lag).
    #[default]
    Wetted,
    /// The stone's radius R (the reduced form of whole_throw_memory.md §3 item B: τ = κ R/|U|).
    Radius,
}

/// `physics.wetted_memory`: τ = `lag` · L/|U|.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MemoryParams {
    /// λ (with L = s_g) or κ (with L = R), dimensionless.
    pub lag: f64,
    /// Which length L the lag scales: the wetted length s_g or the radius R.
    pub length: LagLength,
    /// Π_c: the lag shortens with the contact's reduced frequency Π = |ṡ_g|/|U| as
    /// τ = λ L/(|U| (1 + Π/Π_c)), the linearised Wagner strip's lag against its reduced frequency
    /// (docs/studies/wagner_lag, its b/s = 2–3 curves: Π_c ≈ 0.09–0.15). `None` (omitted): a lag
    /// that does not depend on Π, the law of every preset written before this field.
    pub strip_frequency: Option<f64>,
    /// A: Wagner's entry lead, dd_e/dt = A·max(ḋ_g, 0) + (d_g − d_e)/τ: the wetted extent of an
    /// entering body outruns the geometric intersection (Wagner 1932). 0 (omitted): relaxation
    /// alone, the law of every preset written before this field.
    pub entry_lead: f64,
}

impl Default for MemoryParams {
    fn default() -> Self {
        Self {
            lag: 2.0,
            length: LagLength::Wetted,
            strip_frequency: None,
            entry_lead: 0.0,
        }
    }
}

impl Physics {
    /// The base of the preset being parsed (see [`with_schema`]).
    fn omitted() -> Self {
        Preset::omitted().physics
    }

    /// A `version: 1` preset's omitted physics (see [`Preset::version_1`]).
    pub fn version_1() -> Self {
        Self {
            gravity: 9.81,
            water_density: 1000.0,
            force_law: ForceLaw::Rosellini,
            lift_coefficient: None,
            friction_coefficient: None,
            ventilated: true,
            integrator: Integrator::Adaptive,
            tolerance: 1e-6,
            rotation: Rotation::Locked,
            retired_pressure_centre: RetiredSettings,
            pressure_sign: PressureSign::AsPrinted,
            axial_spin: AxialSpin::Faceted,
            buoyancy: false,
            hydrostatic: Hydrostatic::LoadedFaces,
            air: None,
            dt: 0.005,
            max_time: 20.0,
            steps_across_ticks: false,
            wetted_memory: None,
        }
    }
}

impl Physics {
    /// (C_l, C_f) in force: the preset's, or the law's defaults.
    pub fn coefficients(&self) -> (f64, f64) {
        let (cl, cf) = self.force_law.default_coefficients();
        (
            self.lift_coefficient.unwrap_or(cl),
            self.friction_coefficient.unwrap_or(cf),
        )
    }
}

/// How the water grid keeps every column's volume non-negative (eq. 40; `water.limiter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Limiter {
    /// Mei et al. 2007's K factor per source column: exact conservation, V ≥ 0.
    MassConserving,
    /// The paper's eq. 41: a negative change is set to zero (creates or destroys water).
    PaperClamp,
}

/// Storage precision of the water grid's depths and flows. The kernel is memory-bound, so f32 halves
/// its traffic; sums that must conserve volume are formed in f64 either way (water.rs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum Precision {
    /// 4-byte floats: what a rendered lake needs (volume conserved to ~1e-7 relative).
    #[default]
    F32,
    /// 8-byte floats: volume conserved to rounding (~1e-15), for validation.
    F64,
}

/// A swell the water starts with (`water.swell`): a travelling wave η = A sin(k n·x) over the
/// whole grid, k = 2π/wavelength, n along `heading_deg`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Swell {
    /// m
    pub amplitude: f64,
    /// m
    pub wavelength: f64,
    /// Direction the swell travels, degrees from +x.
    pub heading_deg: f64,
}

impl Default for Swell {
    fn default() -> Self {
        Self {
            amplitude: 0.02,
            wavelength: 3.0,
            heading_deg: 90.0,
        }
    }
}

/// The preset's water (`water`): the lake's extent and the column-and-pipe grid's resolution,
/// depth and numerics (`water/`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default = "WaterParams::omitted", deny_unknown_fields)]
pub struct WaterParams {
    /// Simulate the lake's columns; false: no grid, the stone meets the plane z = 0 and the run
    /// leaves the domain 1 km from the launch.
    pub enabled: bool,
    /// Contact and clipping against the water grid's height instead of z = 0.
    pub wavy_contact: bool,
    /// m (x, y)
    pub size: [f64; 2],
    /// The grid's −x, −y corner; `None`: launch point 2 m inside the −x edge, centred in y. Always
    /// saved (the shipped default names one, so `None` must be written to mean `None` in a
    /// `version: 2` file).
    #[serde(
        deserialize_with = "de_plain_option",
        serialize_with = "ser_plain_option"
    )]
    pub origin: Option<[f64; 2]>,
    /// m
    pub cell: f64,
    /// m: rest depth H (wave speed √(gH)).
    pub depth: f64,
    /// 1/s
    pub damping: f64,
    /// Add the four diagonal pipes to the four axis pipes (the isotropic 9-point stencil).
    pub diagonal_pipes: bool,
    /// How a column is kept from a negative volume (eq. 40).
    pub limiter: Limiter,
    /// Storage precision of depths and flows.
    pub precision: Precision,
    /// A swell the water starts with; `None`: still water.
    pub swell: Option<Swell>,
    /// `near_field: Columns`, which presets saved before the field was folded away write: read and
    /// ignored, never written (`Spectral` fails as retired).
    #[serde(
        default,
        rename = "near_field",
        skip_serializing,
        deserialize_with = "read_near_field"
    )]
    pub retired_near_field: RetiredSettings,
    /// The retired spectral near field's settings, which every preset saved before issue 40 wrote
    /// out (`spectral: (cells: 128, …)`): read and ignored, never written.
    #[serde(
        default,
        rename = "spectral",
        skip_serializing,
        deserialize_with = "skip_retired"
    )]
    pub retired_spectral: RetiredSettings,
    /// s: the longest water step of the columns; omitted: the automatic step, [`COURANT_SAFETY`]
    /// of the Courant limit (numerics only: a shorter step is always stable; fidelity study §11
    /// refines it with the tick).
    ///
    /// [`COURANT_SAFETY`]: crate::sim::water::COURANT_SAFETY
    #[serde(
        deserialize_with = "de_plain_option",
        serialize_with = "ser_plain_option",
        skip_serializing_if = "Option::is_none"
    )]
    pub max_step: Option<f64>,
}

/// Every value `water.near_field` ever took. The field is folded away: with wavy contact the
/// stone touches the lake's columns, the only surface left, so `Columns`, which every preset saved
/// before wrote, is read and ignored; the spectral near field is retired.
#[derive(Deserialize)]
enum NearFieldName {
    Columns,
    Spectral,
}

fn read_near_field<'de, D: Deserializer<'de>>(d: D) -> Result<RetiredSettings, D::Error> {
    match NearFieldName::deserialize(d)? {
        NearFieldName::Columns => Ok(RetiredSettings),
        NearFieldName::Spectral => Err(serde::de::Error::custom(Retired {
            field: "water.near_field",
            value: "Spectral",
            why: "the stone reads only the ambient water since the wetted-extent memory, so no \
                  shipped preset touched a near field; leave the field out (with wavy contact the stone \
                  touches the columns)",
        })),
    }
}

/// A retired group of settings that old presets still name: read whatever it holds, keep nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct RetiredSettings;

fn skip_retired<'de, D: Deserializer<'de>>(deserializer: D) -> Result<RetiredSettings, D::Error> {
    serde::de::IgnoredAny::deserialize(deserializer).map(|_| RetiredSettings)
}

impl WaterParams {
    /// The base of the preset being parsed (see [`with_schema`]).
    fn omitted() -> Self {
        Preset::omitted().water
    }

    /// A `version: 1` preset's omitted water (see [`Preset::version_1`]).
    pub fn version_1() -> Self {
        Self {
            enabled: true,
            wavy_contact: false,
            size: [40.0, 12.0],
            origin: None,
            cell: 0.05,
            depth: 0.3,
            damping: 0.05,
            diagonal_pipes: true,
            limiter: Limiter::MassConserving,
            precision: Precision::F32,
            swell: None,
            retired_near_field: RetiredSettings,
            retired_spectral: RetiredSettings,
            max_step: None,
        }
    }
}

impl WaterParams {
    /// The grid's −x, −y corner for a throw launched at `launch_xy`.
    pub fn origin_for(&self, launch_xy: [f64; 2]) -> [f64; 2] {
        self.origin
            .unwrap_or([launch_xy[0] - 2.0, launch_xy[1] - 0.5 * self.size[1]])
    }
}

/// Accepts a plain value (`0.5`) or `Some(0.5)` for an optional field, as the preset contract writes it.
fn de_plain_option<'de, D, T>(deserializer: D) -> Result<Option<T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum PlainOrOption<T> {
        Plain(T),
        Option(Option<T>),
    }
    Ok(match PlainOrOption::<T>::deserialize(deserializer)? {
        PlainOrOption::Plain(v) => Some(v),
        PlainOrOption::Option(v) => v,
    })
}

fn ser_plain_option<S, T>(value: &Option<T>, serializer: S) -> Result<S::Ok, S::Error>
where
    S: Serializer,
    T: Serialize,
{
    match value {
        Some(v) => v.serialize(serializer),
        None => serializer.serialize_none(),
    }
}

// ---------------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------------

/// Largest launch speed accepted (m/s): well past any human throw (record arm speed ≈ 22 m/s).
pub(crate) const MAX_SPEED: f64 = 100.0;
/// Largest spin accepted (rad/s): ≈ 160 rev/s, past the 65 rev/s of Clanet's launcher and the
/// ~50 rev/s of the best human throws.
pub(crate) const MAX_SPIN: f64 = 1000.0;
/// Tick bounds (s).
pub const DT_RANGE: (f64, f64) = (1e-6, 0.05);
/// Most columns a water grid may have (memory and real-time bound).
pub const MAX_WATER_COLUMNS: usize = 4_000_000;

fn check_range(field: &str, value: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ParamError> {
    if !value.is_finite() {
        return Err(ParamError::new(
            field,
            format!("expected a finite number in [{lo}, {hi}] {unit}, found {value}"),
        ));
    }
    if value < lo || value > hi {
        return Err(ParamError::new(
            field,
            format!("expected a number in [{lo}, {hi}] {unit}, found {value}"),
        ));
    }
    Ok(())
}

/// What the `version` field may hold, for a message about `found`.
pub(crate) fn schema_expected(found: u32) -> String {
    format!(
        "expected 1 (omitted fields: the model before the fidelity work) or 2 (omitted fields: \
         the shipped default), found {found}"
    )
}

fn check_positive(field: &str, value: f64, hi: f64, unit: &str) -> Result<(), ParamError> {
    if !value.is_finite() || value <= 0.0 || value > hi {
        return Err(ParamError::new(
            field,
            format!("expected a positive number up to {hi} {unit}, found {value}"),
        ));
    }
    Ok(())
}

impl Preset {
    /// Checks every field's range; the first problem found is returned.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(1..=LATEST_SCHEMA).contains(&self.version) {
            return Err(ParamError::new("version", schema_expected(self.version)));
        }
        self.stone.validate()?;
        self.launch.validate()?;
        self.physics.validate()?;
        self.water.validate()?;
        self.check_quadrature()
    }

    /// `stone.quadrature: Smooth` integrates over a smooth body of revolution, so its spin must be
    /// smooth too. (Over wavy water the mesh's faces carry the load: `hydro::evaluate`.)
    pub fn check_quadrature(&self) -> Result<(), ParamError> {
        if self.stone.quadrature.is_faces() {
            return Ok(());
        }
        let refuse = |field: &str, why: &str| {
            Err(ParamError::new(
                field,
                format!("{why} with stone.quadrature: Smooth"),
            ))
        };
        if self.physics.rotation == Rotation::Free && !self.physics.axial_spin.is_smooth() {
            return refuse(
                "physics.axial_spin",
                "expected Resal (a smooth body has no facets to turn)",
            );
        }
        Ok(())
    }
}

impl StoneParams {
    /// Checks the shape's dimensions, the mass, the mesh resolution and the quadrature; the first
    /// problem found is returned.
    pub fn validate(&self) -> Result<(), ParamError> {
        match self.shape {
            Shape::Disk { radius, thickness } | Shape::Lens { radius, thickness } => {
                check_positive("stone.shape.radius", radius, 1.0, "m")?;
                check_positive("stone.shape.thickness", thickness, 0.5, "m")?;
                if thickness > 2.0 * radius {
                    return Err(ParamError::new(
                        "stone.shape.thickness",
                        format!(
                            "expected at most the diameter {} m (a thin body of revolution), found {thickness}",
                            2.0 * radius
                        ),
                    ));
                }
            }
            Shape::Plate {
                length,
                width,
                thickness,
            } => {
                check_positive("stone.shape.length", length, 2.0, "m")?;
                check_positive("stone.shape.width", width, 2.0, "m")?;
                check_positive("stone.shape.thickness", thickness, 0.5, "m")?;
            }
        }
        check_positive("stone.mass", self.mass, 100.0, "kg")?;
        if !(8..=256).contains(&self.segments) {
            return Err(ParamError::new(
                "stone.segments",
                format!("expected an integer in [8, 256], found {}", self.segments),
            ));
        }
        if let Some(bands) = self.bands {
            if !(4..=128).contains(&bands) {
                return Err(ParamError::new(
                    "stone.bands",
                    format!("expected an integer in [4, 128], found {bands}"),
                ));
            }
        }
        // A disk or a plate with `Smooth` is loaded through its faces (`Stone::new`): the shipped
        // lenses are smooth, so a shape changed in the app or in a version-2 file keeps working.
        if let Quadrature::Smooth { meridian, around } = self.quadrature {
            for (field, n) in [("meridian", meridian), ("around", around)] {
                if !(2..=64).contains(&n) {
                    return Err(ParamError::new(
                        format!("stone.quadrature.{field}"),
                        format!("expected an integer in [2, 64], found {n}"),
                    ));
                }
            }
        }
        Ok(())
    }
}

impl Launch {
    /// Checks the position (a height in [−0.5, 100] m), the speed, the attitude and the spin; the
    /// first problem found is returned.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            check_range(
                &format!("launch.position.{axis}"),
                self.position[i],
                -1000.0,
                1000.0,
                "m",
            )?;
            check_range(
                &format!("launch.velocity.{axis}"),
                self.velocity[i],
                -MAX_SPEED,
                MAX_SPEED,
                "m/s",
            )?;
            check_range(
                &format!("launch.angular_velocity.{axis}"),
                self.angular_velocity[i],
                -MAX_SPIN,
                MAX_SPIN,
                "rad/s",
            )?;
        }
        if self.position[2] < -0.5 || self.position[2] > 100.0 {
            return Err(ParamError::new(
                "launch.position.z",
                format!(
                    "expected a height in [-0.5, 100] m above the water, found {}",
                    self.position[2]
                ),
            ));
        }
        let speed =
            (self.velocity[0].powi(2) + self.velocity[1].powi(2) + self.velocity[2].powi(2)).sqrt();
        if speed > MAX_SPEED {
            return Err(ParamError::new(
                "launch.velocity",
                format!("expected a speed up to {MAX_SPEED} m/s, found {speed}"),
            ));
        }
        check_range(
            "launch.attitude.tilt_deg",
            self.attitude.tilt_deg,
            -90.0,
            90.0,
            "degrees",
        )?;
        check_range(
            "launch.attitude.bank_deg",
            self.attitude.bank_deg,
            -90.0,
            90.0,
            "degrees",
        )?;
        check_range(
            "launch.attitude.heading_deg",
            self.attitude.heading_deg,
            -360.0,
            360.0,
            "degrees",
        )?;
        check_range("launch.spin", self.spin, -MAX_SPIN, MAX_SPIN, "rad/s")?;
        Ok(())
    }
}

impl Physics {
    /// Checks the constants, the coefficients, the air, the memory's lag, the tick and the time
    /// limit; the first problem found is returned.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("physics.gravity", self.gravity, 0.0, 100.0, "m/s²")?;
        check_positive(
            "physics.water_density",
            self.water_density,
            20_000.0,
            "kg/m³",
        )?;
        if let Some(cl) = self.lift_coefficient {
            check_range("physics.lift_coefficient", cl, 0.0, 10.0, "")?;
        }
        if let Some(cf) = self.friction_coefficient {
            check_range("physics.friction_coefficient", cf, 0.0, 10.0, "")?;
        }
        check_range("physics.tolerance", self.tolerance, 1e-12, 1e-2, "")?;
        if let Some(m) = self.wetted_memory {
            check_positive("physics.wetted_memory.lag", m.lag, 100.0, "")?;
            if let Some(pc) = m.strip_frequency {
                check_positive("physics.wetted_memory.strip_frequency", pc, 100.0, "")?;
            }
            check_range(
                "physics.wetted_memory.entry_lead",
                m.entry_lead,
                0.0,
                2.0,
                "",
            )?;
        }
        if let Some(a) = self.air {
            check_range("physics.air.density", a.density, 0.0, 100.0, "kg/m³")?;
            check_range("physics.air.lift_slope", a.lift_slope, 0.0, 20.0, "1/rad")?;
            check_range("physics.air.drag_zero", a.drag_zero, 0.0, 10.0, "")?;
            check_range("physics.air.drag_slope", a.drag_slope, 0.0, 20.0, "1/rad²")?;
            check_range(
                "physics.air.moment_slope",
                a.moment_slope,
                -10.0,
                10.0,
                "1/rad",
            )?;
        }
        check_range("physics.dt", self.dt, DT_RANGE.0, DT_RANGE.1, "s")?;
        check_positive("physics.max_time", self.max_time, 3600.0, "s")?;
        Ok(())
    }
}

impl WaterParams {
    /// Checks the lake's size, origin, cell, depth, damping, step and swell, and that an enabled
    /// grid has between 4 cells across and [`MAX_WATER_COLUMNS`] columns; the first problem found
    /// is returned.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_positive("water.size.x", self.size[0], 2000.0, "m")?;
        check_positive("water.size.y", self.size[1], 2000.0, "m")?;
        if let Some(o) = self.origin {
            check_range("water.origin.x", o[0], -10_000.0, 10_000.0, "m")?;
            check_range("water.origin.y", o[1], -10_000.0, 10_000.0, "m")?;
        }
        check_range("water.cell", self.cell, 0.005, 5.0, "m")?;
        check_range("water.depth", self.depth, 0.01, 100.0, "m")?;
        check_range("water.damping", self.damping, 0.0, 100.0, "1/s")?;
        if let Some(m) = self.max_step {
            check_range("water.max_step", m, 1e-5, 0.1, "s")?;
        }
        if self.enabled {
            let nx = (self.size[0] / self.cell).ceil();
            let ny = (self.size[1] / self.cell).ceil();
            if nx < 4.0 || ny < 4.0 {
                return Err(ParamError::new(
                    "water.cell",
                    format!("expected at least 4 cells across the grid, found {nx} × {ny}"),
                ));
            }
            if nx * ny > MAX_WATER_COLUMNS as f64 {
                return Err(ParamError::new(
                    "water.cell",
                    format!(
                        "expected at most {MAX_WATER_COLUMNS} columns, found {} ({nx} × {ny}): use larger cells or a smaller lake",
                        nx * ny
                    ),
                ));
            }
        }
        if let Some(s) = self.swell {
            check_range(
                "water.swell.amplitude",
                s.amplitude,
                0.0,
                0.5 * self.depth,
                "m (half the depth at most)",
            )?;
            check_positive("water.swell.wavelength", s.wavelength, 1000.0, "m")?;
            check_range(
                "water.swell.heading_deg",
                s.heading_deg,
                -360.0,
                360.0,
                "degrees",
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_preset_is_valid() {
        Preset::version_1().validate().unwrap();
    }

    #[test]
    fn plain_and_some_coefficients_both_parse() {
        let a: Physics = ron::from_str("(lift_coefficient: 0.7)").unwrap();
        let b: Physics = ron::from_str("(lift_coefficient: Some(0.7))").unwrap();
        assert_eq!(a.lift_coefficient, Some(0.7));
        assert_eq!(b.lift_coefficient, Some(0.7));
        let c: Physics = ron::from_str("()").unwrap();
        assert_eq!(c.coefficients(), ForceLaw::Rosellini.default_coefficients());
    }

    #[test]
    fn negative_mass_is_refused_with_field() {
        let mut p = Preset::version_1();
        p.stone.mass = -1.0;
        let e = p.validate().unwrap_err();
        assert_eq!(e.field, "stone.mass");
    }

    #[test]
    fn nan_is_refused() {
        let mut p = Preset::version_1();
        p.launch.velocity[0] = f64::NAN;
        assert_eq!(p.validate().unwrap_err().field, "launch.velocity.x");
    }
}
