//! What a whole throw did, read off its [`Summary`]: the checks of `../shared/reference/whole_throw.md`
//! §5 (Hewitt et al. 2011: no steady planing well above the minimal speed; the record runs' quick tail
//! of tiny hops, "pitty-pat"; Tang et al. 2021: the curve). Pure functions of the contact list, so the
//! tests, the fidelity study and the app read a throw the same way.

use super::Summary;

/// A throw's shape: how far, how many skips, and how it ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThrowShape {
    pub skips: usize,
    /// Horizontal distance from the launch to where the run ended (m).
    pub distance: f64,
    /// Horizontal distance covered during the last contact episode (m): a planing glide when large.
    pub final_contact_length: f64,
    /// `final_contact_length / distance` (0 when the stone never moved).
    pub final_share: f64,
    /// Duration of the last contact (s).
    pub final_duration: f64,
    /// Longest contact before the last one (s); 0 with fewer than two contacts.
    pub longest_earlier_contact: f64,
    /// Longest distance between successive touchdowns over the last quarter of the touchdowns (m);
    /// 0 with fewer than 8 contacts.
    pub tail_longest_hop: f64,
    /// Sideways position of the centre of mass (m) at the last touchdown, relative to the launch.
    pub lateral: f64,
}

/// Reads a throw's shape from its summary; `launch` is the launch position's (x, y).
pub fn throw_shape(s: &Summary, launch: [f64; 2]) -> ThrowShape {
    let from_launch = |x: f64, y: f64| ((x - launch[0]).powi(2) + (y - launch[1]).powi(2)).sqrt();
    let c = &s.contacts;
    let (final_contact_length, final_duration, lateral) = match c.last() {
        Some(last) => (
            (s.distance - from_launch(last.x, last.y)).max(0.0),
            last.t_end - last.t_start,
            last.y - launch[1],
        ),
        None => (0.0, 0.0, 0.0),
    };
    let longest_earlier_contact = c
        .iter()
        .rev()
        .skip(1)
        .map(|e| e.t_end - e.t_start)
        .fold(0.0, f64::max);
    let tail_longest_hop = if c.len() >= 8 {
        let tail = &c[c.len() * 3 / 4..];
        tail.windows(2)
            .map(|w| ((w[1].x - w[0].x).powi(2) + (w[1].y - w[0].y).powi(2)).sqrt())
            .fold(0.0, f64::max)
    } else {
        0.0
    };
    ThrowShape {
        skips: s.skips,
        distance: s.distance,
        final_contact_length,
        final_share: if s.distance > 0.0 {
            final_contact_length / s.distance
        } else {
            0.0
        },
        final_duration,
        longest_earlier_contact,
        tail_longest_hop,
        lateral,
    }
}

/// The "no hovercraft" rule of issue 11: a throw that skips at least twice ends with a contact that
/// covers at most `max_share` of its distance, and no earlier contact lasts longer than
/// `max_contact` seconds. `None` when it holds (or the throw skipped fewer than twice), else why not.
pub fn hovercraft(shape: &ThrowShape, max_share: f64, max_contact: f64) -> Option<String> {
    if shape.skips < 2 {
        return None;
    }
    if shape.final_share > max_share {
        return Some(format!(
            "the last contact covers {:.0} % of the distance ({:.2} m of {:.2} m)",
            100.0 * shape.final_share,
            shape.final_contact_length,
            shape.distance
        ));
    }
    if shape.longest_earlier_contact > max_contact {
        return Some(format!(
            "an earlier contact lasts {:.3} s",
            shape.longest_earlier_contact
        ));
    }
    None
}

/// Least-squares slope of ln y over ln x (the exponent p of y ∝ x^p, e.g. skips against spin);
/// `None` below two positive points.
pub fn fit_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ContactEvent;

    fn contact(t0: f64, t1: f64, x: f64) -> ContactEvent {
        ContactEvent {
            t_start: t0,
            t_end: t1,
            skip: true,
            graze: false,
            x,
            y: 0.0,
            v_in: [0.0; 3],
            v_out: [0.0; 3],
            attitude_in: [0.0; 3],
            attitude_out: [0.0; 3],
            beta_in: 0.0,
            open: false,
        }
    }

    fn summary(contacts: Vec<ContactEvent>, distance: f64) -> Summary {
        Summary {
            schema: 1,
            name: String::new(),
            outcome: None,
            skips: contacts.len().saturating_sub(1),
            distance,
            final_time: 0.0,
            steps: 0,
            force_evals: 0,
            contacts,
            water: None,
            diverged_reason: None,
        }
    }

    #[test]
    fn a_long_last_contact_is_a_glide() {
        let s = summary(
            vec![
                contact(0.1, 0.12, 1.0),
                contact(0.3, 0.32, 3.0),
                contact(0.5, 3.0, 5.0),
            ],
            20.0,
        );
        let t = throw_shape(&s, [0.0, 0.0]);
        assert!((t.final_contact_length - 15.0).abs() < 1e-12);
        assert!((t.final_share - 0.75).abs() < 1e-12);
        assert!((t.longest_earlier_contact - 0.02).abs() < 1e-12);
        assert!(hovercraft(&t, 0.1, 0.3).is_some());
    }

    #[test]
    fn tail_hops_are_measured_over_the_last_quarter() {
        let xs = [1.0, 3.0, 4.5, 5.5, 6.2, 6.6, 6.9, 7.1];
        let s = summary(
            xs.iter()
                .enumerate()
                .map(|(i, &x)| contact(i as f64, i as f64 + 0.01, x))
                .collect(),
            7.2,
        );
        let t = throw_shape(&s, [0.0, 0.0]);
        assert!(
            (t.tail_longest_hop - 0.2).abs() < 1e-12,
            "{}",
            t.tail_longest_hop
        );
        assert!(hovercraft(&t, 0.1, 0.3).is_none());
    }
}
