//! The touch search: where along a step the stone first meets the water. Along the exact flight
//! ([`first_touch`]) the clearance is bounded from below between samples — by the stone's fall,
//! the turning of its axis ([`RevolutionBound`]) and the waves' highest point ([`WaveBound`]) — and
//! the interval halved where the bound allows a touch, so a graze inside a tick is found, not
//! sampled past; inside a contact step the first wet offset is bisected or found by the Illinois
//! rule ([`first_wet`], [`first_wet_by`], [`first_wet_between`]). Event location as in Hairer,
//! Nørsett & Wanner, *Solving ODEs I*, §II.6.

use super::air::AIR_SUBSTEP;
use super::integrate::BodyState;

/// Depth of the halvings of [`first_touch`]: a flight interval is cut into at most 2¹² parts, so a
/// graze shallower than `rate × h / 2¹³` (µm at the speeds and steps of the presets) is not resolved.
pub(crate) const TOUCH_SEARCH_DEPTH: u32 = 12;

/// What the clearance search along an exact flight needs besides the flight itself.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FlightBound {
    /// Largest rate (m/s) at which the lowest vertex's clearance *relative to the centre of mass's
    /// height* can change: ω_max R (the vertices turn about the centre, |ω| ≤ |L|/I_min) plus
    /// S (|v_h| + ω_max R) (the surface under a vertex, of slope at most S, passing at most that
    /// fast). Zero for a locked attitude over flat water. The surface is the grid's bilinear one,
    /// frozen during a tick; beyond the grid's edge η drops to 0, a step no slope covers (the stone
    /// leaves the domain there).
    pub rate: f64,
    /// A lower bound of that relative clearance at all times: −R − max η.
    pub floor: f64,
    /// Bound of the air's acceleration (m/s², 0 without air): the centre's height is then no
    /// longer a parabola but can dip below its chord over [a, b] by at most
    /// `lift · w (w + AIR_SUBSTEP) / 4` (w = b − a; the kicks come every substep).
    pub lift: f64,
    /// A second bound for a body of revolution (see [`FlightBound::with_revolution`]): the rate
    /// without the spin about the symmetry axis, and the facet gap it costs. `None`: only `rate`.
    pub revolution: Option<RevolutionBound>,
}

/// The clearance bound of a body whose vertices lie on rings about its symmetry axis, at n
/// azimuths each. Let C be the clearance of the rings themselves (every point of every ring, not
/// only the vertices): a spin about the axis maps the rings onto themselves, so C moves only with
/// the axis (|ω⊥| = |L × a| / I₁) and the translation, at most at `rate` (relative to the centre's
/// height, as [`FlightBound::rate`]). The vertices' clearance c is never below C, and never above it
/// by more than `facet` (the nearest vertex to the lowest ring point is at most a chord
/// 2r sin(π/2n) away, over which the height and the surface under it change by at most
/// (1 + S) times that; on flat water the sampled cosine's own gap r(1 − cos π/n)). So
/// c(t) ≥ c(a) − facet − rate (t − a): without the spin's ωR, which dominates `rate` for a
/// fast-spun stone (a 30 rev/s pebble's rim moves at 11 m/s).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RevolutionBound {
    pub rate: f64,
    pub facet: f64,
}

impl FlightBound {
    /// For a stone of bounding radius `radius` in flight with horizontal speed `speed_h`, angular
    /// speed at most `omega`, over a surface of slope at most `slope` and height at most `max_eta`.
    pub fn new(radius: f64, speed_h: f64, omega: f64, slope: f64, max_eta: f64) -> Self {
        Self {
            rate: clearance_rate(radius, speed_h, omega, slope),
            floor: -radius - max_eta.max(0.0),
            lift: 0.0,
            revolution: None,
        }
    }

    /// With the second bound of a body of revolution ([`RevolutionBound`]): `omega_perp` bounds
    /// the angular speed of its symmetry axis, `facet` the vertices' gap above the rings.
    pub fn with_revolution(
        self,
        radius: f64,
        speed_h: f64,
        omega_perp: f64,
        slope: f64,
        facet: f64,
    ) -> Self {
        Self {
            revolution: Some(RevolutionBound {
                rate: clearance_rate(radius, speed_h, omega_perp, slope),
                facet: if facet.is_nan() { f64::INFINITY } else { facet },
            }),
            ..self
        }
    }

    /// The same bound for a flight with the air's acceleration bounded by `lift` (m/s²).
    pub fn with_air(self, lift: f64) -> Self {
        Self {
            lift: if lift.is_nan() { f64::INFINITY } else { lift },
            ..self
        }
    }
}

/// ω R + S (|v_h| + ω R): how fast the lowest vertex's clearance relative to the centre's height
/// can change (see [`FlightBound::rate`]); ∞ for a NaN input.
fn clearance_rate(radius: f64, speed_h: f64, omega: f64, slope: f64) -> f64 {
    let turn = omega * radius;
    let rate = turn + slope * (speed_h + turn);
    if rate.is_nan() {
        f64::INFINITY
    } else {
        rate
    }
}

/// A sample of the flight: offset t, the state there, the lowest vertex's clearance c(t) (a lower
/// bound of it, as `lowest_clearance` gives) and, with a [`WaveBound`], the lowest vertex's height
/// relative to the centre of mass (its rise, whatever the water).
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    state: BodyState,
    c: f64,
    rise: f64,
}

/// A second clearance bound over a wavy surface, for when the slope's term in
/// [`FlightBound::rate`] (S |v_h|: several m/s over a wake) is what keeps an interval from being
/// cleared. Over [a, b] the lowest vertex stands at least min(z_a, z_b) + min rise above the rest
/// level (the rise, flat water's own relative clearance, changes only with the attitude, at
/// `rate`, or as `revolution` bounds it), and the surface under the stone is at most the highest η
/// over the rectangle its vertices can sweep: the chord of the centre's horizontal path, widened
/// by the stone's radius and by the bow the air's acceleration `drift` allows.
pub(crate) struct WaveBound<'a> {
    /// The lowest vertex's height relative to the centre of mass (flat water's clearance − z).
    pub rise: &'a dyn Fn(&BodyState) -> f64,
    /// The highest η of the surface over the rectangle [lo, hi] (world x, y).
    pub crest: &'a dyn Fn([f64; 2], [f64; 2]) -> f64,
    /// Bounding radius (m).
    pub radius: f64,
    /// ω R: how fast the rise can change (m/s).
    pub rate: f64,
    /// For a body of revolution: the rise's rate without the spin, and the facet gap on flat water.
    pub revolution: Option<RevolutionBound>,
    /// Bound of the air's acceleration (m/s², 0 without air).
    pub drift: f64,
}

/// What [`first_touch`] reads of the flight.
struct Probe<'a> {
    fly: &'a dyn Fn(&BodyState, f64) -> BodyState,
    clear: &'a dyn Fn(&BodyState) -> f64,
    bound: &'a FlightBound,
    wave: Option<&'a WaveBound<'a>>,
}

impl Probe<'_> {
    fn sample(&self, t: f64, state: BodyState) -> Sample {
        Sample {
            t,
            state,
            c: (self.clear)(&state),
            rise: self.wave.map_or(f64::NAN, |w| (w.rise)(&state)),
        }
    }

    /// Whether the bounds prove c > 0 over [a, b].
    fn clears(&self, a: &Sample, b: &Sample) -> bool {
        let bound = self.bound;
        let width = b.t - a.t;
        let (za, zb) = (a.state.position.z, b.state.position.z);
        let (ga, gb) = (a.c - za, b.c - zb);
        let g_min = lowest_of_both((ga, gb), bound.rate, bound.revolution, width);
        let low = za.min(zb) - air_bow(bound.lift, width);
        if low + g_min.max(bound.floor) > 0.0 {
            return true;
        }
        let Some(w) = self.wave else { return false };
        let rise = lowest_of_both((a.rise, b.rise), w.rate, w.revolution, width);
        let reach = w.radius + air_bow(w.drift, width);
        let (pa, pb) = (a.state.position, b.state.position);
        let lo = [pa.x.min(pb.x) - reach, pa.y.min(pb.y) - reach];
        let hi = [pa.x.max(pb.x) + reach, pa.y.max(pb.y) + reach];
        let rounding = 1e-12 * (w.radius + za.abs().max(zb.abs()));
        low + rise.max(-w.radius) - (w.crest)(lo, hi) > rounding
    }

    /// [`first_touch`] on [a.t, b.t], c(a) > 0.
    fn search(&self, a: Sample, b: Sample, depth: u32) -> Option<(f64, f64)> {
        if self.clears(&a, &b) {
            return None;
        }
        if depth >= TOUCH_SEARCH_DEPTH {
            return (b.c <= 0.0).then_some((a.t, b.t));
        }
        let half = 0.5 * (b.t - a.t);
        let m = self.sample(a.t + half, (self.fly)(&a.state, half));
        let left = self.search(a, m, depth + 1);
        if m.c <= 0.0 {
            return left.or(Some((a.t, m.t)));
        }
        left.or_else(|| self.search(m, b, depth + 1))
    }
}

/// The first touch along an exact flight from `s` over [0, h]: `None` when the stone is proven
/// clear of the water over the whole interval, else `(dry, wet)` with c(dry) > 0 (clear over
/// [0, dry]) and c(wet) ≤ 0, bracketing the first touch for a bisection (`(0, 0)` when already
/// touching). `fly(state, t)` is the exact flight over t, `clear(state)` the clearance.
///
/// Write c(t) = z(t) + g(t): the centre's height z is a parabola (concave), and g, the lowest
/// vertex's clearance relative to it, changes at most at `bound.rate` and never falls below
/// `bound.floor`. So over [a, b], c ≥ min(z_a, z_b) + min g, with g bounded below by the lines
/// g_a − rate (t − a) and g_b − rate (b − t). With rate 0 (a locked attitude over flat water) c is
/// concave and the two ends decide exactly. Otherwise an interval the bounds (this one, the
/// revolution's and the wave's) cannot clear is halved, left half first, until it is cleared or
/// a wet point is found, at most [`TOUCH_SEARCH_DEPTH`] times; each midpoint is flown to from its
/// interval's start, so a general body's integrated torque-free rotation costs the flight's length
/// once per level, not per sample.
pub(crate) fn first_touch(
    fly: &dyn Fn(&BodyState, f64) -> BodyState,
    clear: &dyn Fn(&BodyState) -> f64,
    bound: &FlightBound,
    wave: Option<&WaveBound>,
    s: &BodyState,
    h: f64,
) -> Option<(f64, f64)> {
    let probe = Probe {
        fly,
        clear,
        bound,
        wave,
    };
    let a = probe.sample(0.0, *s);
    if a.c <= 0.0 {
        return Some((0.0, 0.0));
    }
    let b = probe.sample(h, fly(s, h));
    if bound.rate == 0.0 && bound.lift == 0.0 {
        return (b.c <= 0.0).then_some((0.0, h));
    }
    probe.search(a, b, 0)
}

/// How far a flight under an acceleration of at most `accel` (the air's, kicked every substep)
/// can bow from its chord over an interval of `width`: `accel · w (w + AIR_SUBSTEP) / 4`.
fn air_bow(accel: f64, width: f64) -> f64 {
    accel * width * (width + AIR_SUBSTEP) * 0.25
}

/// [`lowest_between`] of a quantity that changes at most at `rate`, or, for a body of revolution,
/// at `revolution.rate` once its ends are lowered by the facet gap: the better of the two bounds.
fn lowest_of_both(
    (ga, gb): (f64, f64),
    rate: f64,
    revolution: Option<RevolutionBound>,
    width: f64,
) -> f64 {
    let plain = lowest_between(ga, gb, rate * width);
    revolution.map_or(plain, |r| {
        plain.max(lowest_between(ga - r.facet, gb - r.facet, r.rate * width))
    })
}

/// The lowest value over an interval of a function that is `ga` and `gb` at its ends and changes
/// by at most `slack` across it (rate × width): where the two lines g_a − rate (t − a) and
/// g_b − rate (b − t) meet, or the lower end's line at the other end.
fn lowest_between(ga: f64, gb: f64, slack: f64) -> f64 {
    if (ga - gb).abs() >= slack {
        ga.max(gb) - slack
    } else {
        0.5 * (ga + gb - slack)
    }
}

/// Bisection on [lo, hi] for the first offset that is wet, given dry at `lo` and wet at `hi`: at
/// most `iterations` halvings, stopping early when the interval reaches floating-point resolution.
pub(crate) fn first_wet(lo: f64, hi: f64, iterations: u32, wet: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..iterations {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if wet(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The first wet offset in [lo, hi] of a flight whose clearance is `clear(t)`, dry at `lo` and wet
/// at `hi`: Illinois false position on the clearance with the bracket kept (the clearance is smooth
/// along a flight, so it takes a few flights where bisection takes fifty), to floating-point
/// resolution or `iterations` steps; the wet end. Ends that do not bracket fall back to halving
/// on wet or dry, as [`first_wet`].
pub(crate) fn first_wet_by(lo: f64, hi: f64, iterations: u32, clear: impl Fn(f64) -> f64) -> f64 {
    first_wet_between((lo, clear(lo)), (hi, clear(hi)), iterations, clear)
}

/// [`first_wet_by`] from ends whose clearances are known.
pub(crate) fn first_wet_between(
    (mut lo, mut c_lo): (f64, f64),
    (mut hi, mut c_hi): (f64, f64),
    iterations: u32,
    clear: impl Fn(f64) -> f64,
) -> f64 {
    if !(c_lo > 0.0 && c_hi <= 0.0 && c_lo.is_finite() && c_hi.is_finite()) {
        return first_wet(lo, hi, iterations, |t| clear(t) <= 0.0);
    }
    let mut side = 0;
    for _ in 0..iterations {
        let mut t = lo + (hi - lo) * (c_lo / (c_lo - c_hi));
        if !(t > lo && t < hi) {
            t = 0.5 * (lo + hi);
            if t <= lo || t >= hi {
                break;
            }
        }
        let c = clear(t);
        if c <= 0.0 {
            hi = t;
            c_hi = c;
            if side == -1 {
                c_lo *= 0.5;
            }
            side = -1;
        } else {
            lo = t;
            c_lo = c;
            if side == 1 {
                c_hi *= 0.5;
            }
            side = 1;
        }
        if hi - lo <= 2.0 * f64::EPSILON * hi.abs().max(f64::MIN_POSITIVE) {
            break;
        }
    }
    hi
}
