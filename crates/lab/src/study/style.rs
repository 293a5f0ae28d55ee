//! How the studies show things, in one place: the colour palette (Okabe & Ito's colour-blind-safe
//! set, plus black and grey; viridis for ordered values), the display names and colours of the
//! integrators and force laws, and the skip-count classes of the phase maps. Pure data: the chart
//! backend (plotters, behind the `charts` feature) converts [`Rgb`] when it draws.

use stoneskip_physics::sim::params::{ForceLaw, Integrator};

/// An sRGB colour, 8 bits a channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

/// Colours used across the studies (colour-blind-friendly Okabe–Ito palette, plus black).
pub mod colors {
    use super::Rgb;
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const ORANGE: Rgb = Rgb(230, 159, 0);
    pub const SKY: Rgb = Rgb(86, 180, 233);
    pub const GREEN: Rgb = Rgb(0, 158, 115);
    pub const YELLOW: Rgb = Rgb(240, 228, 66);
    pub const BLUE: Rgb = Rgb(0, 114, 178);
    pub const RED: Rgb = Rgb(213, 94, 0);
    pub const PURPLE: Rgb = Rgb(204, 121, 167);
    pub const GREY: Rgb = Rgb(120, 120, 120);
    /// A cycle for numbered series.
    pub const CYCLE: [Rgb; 8] = [BLUE, RED, GREEN, ORANGE, PURPLE, SKY, GREY, BLACK];

    /// Colour `k` of `n` ordered values, dark blue to yellow (viridis, sampled).
    pub fn sequential(k: usize, n: usize) -> Rgb {
        const V: [(f64, f64, f64); 6] = [
            (68.0, 1.0, 84.0),
            (65.0, 68.0, 135.0),
            (42.0, 120.0, 142.0),
            (34.0, 168.0, 132.0),
            (122.0, 209.0, 81.0),
            (220.0, 210.0, 30.0),
        ];
        let t = if n > 1 {
            k as f64 / (n - 1) as f64
        } else {
            0.0
        };
        let x = t.clamp(0.0, 1.0) * (V.len() - 1) as f64;
        let i = (x.floor() as usize).min(V.len() - 2);
        let f = x - i as f64;
        let c = |a: f64, b: f64| (a + (b - a) * f).round().clamp(0.0, 255.0) as u8;
        Rgb(
            c(V[i].0, V[i + 1].0),
            c(V[i].1, V[i + 1].1),
            c(V[i].2, V[i + 1].2),
        )
    }
}

/// Display name of an integrator (as the presets spell it).
pub fn integrator_name(i: Integrator) -> &'static str {
    match i {
        Integrator::Paper => "Paper",
        Integrator::SymplecticEuler => "SymplecticEuler",
        Integrator::Rk4 => "Rk4",
        Integrator::Adaptive => "Adaptive",
    }
}

/// Colour of an integrator in every chart.
pub fn integrator_color(i: Integrator) -> Rgb {
    match i {
        Integrator::Paper => colors::RED,
        Integrator::SymplecticEuler => colors::ORANGE,
        Integrator::Rk4 => colors::BLUE,
        Integrator::Adaptive => colors::GREEN,
    }
}

/// Display name of a force law (as the presets spell it).
pub fn law_name(l: ForceLaw) -> &'static str {
    match l {
        ForceLaw::Rosellini => "Rosellini",
        ForceLaw::Paper => "Paper",
        ForceLaw::Bocquet => "Bocquet",
    }
}

/// Colour of a force law in every chart.
pub fn law_color(l: ForceLaw) -> Rgb {
    match l {
        ForceLaw::Rosellini => colors::BLUE,
        ForceLaw::Paper => colors::RED,
        ForceLaw::Bocquet => colors::GREEN,
    }
}

/// The class of a skip count on the phase maps: 0, 1, 2, 3–4, 5–9, 10+.
pub fn skip_class(skips: usize) -> usize {
    match skips {
        0 => 0,
        1 => 1,
        2 => 2,
        3..=4 => 3,
        5..=9 => 4,
        _ => 5,
    }
}

/// Label and colour of each [`skip_class`], in class order.
pub fn skip_classes() -> Vec<(String, Rgb)> {
    vec![
        ("0: no skip".into(), Rgb(244, 204, 190)),
        ("1 skip".into(), Rgb(222, 235, 247)),
        ("2".into(), Rgb(179, 210, 233)),
        ("3–4".into(), Rgb(120, 175, 215)),
        ("5–9".into(), Rgb(60, 130, 190)),
        ("10+".into(), Rgb(20, 80, 150)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_integrator_and_law_has_its_own_colour() {
        let ic: Vec<Rgb> = Integrator::ALL
            .iter()
            .map(|&i| integrator_color(i))
            .collect();
        let lc: Vec<Rgb> = ForceLaw::ALL.iter().map(|&l| law_color(l)).collect();
        for v in [&ic, &lc] {
            for (a, x) in v.iter().enumerate() {
                assert!(v.iter().skip(a + 1).all(|y| y != x), "{v:?}");
            }
        }
    }

    #[test]
    fn skip_classes_cover_every_count() {
        let n = skip_classes().len();
        for s in 0..40 {
            assert!(skip_class(s) < n);
        }
        assert_eq!(skip_class(4), skip_class(3));
        assert_ne!(skip_class(9), skip_class(10));
    }
}
