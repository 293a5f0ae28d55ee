//! The help overlay (F1 or ?: every shortcut and mouse gesture) and the "about the model" panel:
//! half a page in plain words (what a skip is, what the simulator does, what to try), then each
//! law and option: a plain sentence first, then the detail and its sources (design.md §4–5).

use egui::{RichText, Ui};

/// Every shortcut and gesture: (keys, what it does).
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Space", "throw with the settings"),
    (
        "drag from the stone",
        "throw by hand: direction and speed from the drag (before a throw)",
    ),
    ("P", "pause / resume"),
    ("S", "step exactly one tick"),
    ("R", "reset to the launch point"),
    ("1 / 2 / 3 / 4", "camera: behind, follow (chase), side, top"),
    ("F", "follow the stone"),
    (
        "E",
        "side view: next vertical exaggeration (1×, 5×, 10×, 20×)",
    ),
    ("5 or double-click", "frame the whole trajectory"),
    (
        "drag / right-drag / wheel",
        "orbit / pan / zoom (the camera is then free)",
    ),
    ("F1 or ?", "this help"),
    ("M", "about the model"),
    (
        "X",
        "Experiments: throw many times, changing one thing, and chart the results",
    ),
    ("Esc", "close help and messages"),
];

/// The help overlay's contents.
pub fn help_ui(ui: &mut Ui) {
    egui::Grid::new("help_grid")
        .num_columns(2)
        .spacing([18.0, 4.0])
        .striped(true)
        .show(ui, |ui| {
            for (keys, what) in SHORTCUTS {
                ui.label(RichText::new(*keys).strong().monospace());
                ui.label(*what);
                ui.end_row();
            }
        });
    ui.add_space(6.0);
    ui.weak(
        "Live physics changes apply at the next tick and Replay repeats them at the same ticks; \
         launch, stone and water changes apply on the next throw. Exports go to the folder shown \
         in the Export panel.",
    );
}

/// One item of "The model in detail": a plain first sentence a fifteen-year-old can read, then
/// the detail for a teacher or a researcher, then the sources.
#[derive(Debug, Clone, Copy)]
pub struct ModelItem {
    pub topic: &'static str,
    /// One plain sentence: no symbols, no formulas.
    pub plain: &'static str,
    /// The law or option as the model states it.
    pub detail: &'static str,
    pub sources: &'static str,
}

const fn item(
    topic: &'static str,
    plain: &'static str,
    detail: &'static str,
    sources: &'static str,
) -> ModelItem {
    ModelItem {
        topic,
        plain,
        detail,
        sources,
    }
}

/// "The model in detail", in the order a class meets it; spin leads what turns the stone.
pub const MODEL: &[ModelItem] = &[
    item(
        "Stone",
        "The stone is made of many small flat triangles, like a football is made of patches.",
        "A thin body of revolution (disc, lens) or a plate; its mass is given, its centre and \
         inertia come from the mesh.",
        "the paper §2; Bocquet 2003 (plate)",
    ),
    item(
        "Flight",
        "In the air the stone falls like any thrown ball, and the air can lift and slow it a little.",
        "With the air off, exact ballistic motion under gravity, as in the paper; the shipped \
         pebbles fly through air (see Air in flight): kick–drift–kick around that exact flight.",
        "the paper, eqs. 4–8",
    ),
    item(
        "Spin",
        "Spin keeps the stone steady: each touch of the water turns it a little, less the faster \
         it spins, and a stone kept flat skips more.",
        "Free rotation: a contact's lift acts behind the centre and turns the spinning axis by \
         J·ℓ/(I₃ω). The default throw makes most skips at 15–25 rev/s and fewer towards the held \
         attitude's count at high spin; without spin it dives. The curve as it is, not tuned: no \
         measurement says more spin never costs skips.",
        "Tang et al. 2021; Clanet et al. 2004; docs/studies/whole_throw §6",
    ),
    item(
        "Rotation",
        "The stone can be held at one angle all the way, or left free to turn as the pushes on it \
         turn it.",
        "Locked holds the attitude fixed (the paper's high-spin limit); Free makes the stone a \
         rigid body with torque, spin and gyroscopic stability.",
        "the paper (future work); Rosellini et al. 2005",
    ),
    item(
        "Axial spin",
        "Spinning about its own middle does not stir the water, because the pebble is smooth and \
         round.",
        "Smooth: the pebble stands for a smooth body of revolution, whose spin about its axis \
         moves no water normal to its surface; the facets then neither paddle nor spin it up.",
        "design §4; docs/studies/fidelity",
    ),
    item(
        "Air in flight",
        "Between touches the air lifts a tilted stone a little and slowly rolls it onto its side, \
         like a Frisbee that curves away.",
        "Optional (physics.air): the air lifts, drags and pitches the stone like a spinning disc \
         wing, C_L = C_Lα α, C_D = C_D0 + C_Dα α², C_M = C_Mα α; the nose-up moment rolls a \
         spinning stone by M/(I₃ω) per second, so less spin, more roll. Off: the paper's vacuum.",
        "Crowther & Potts 2007; Hummel 2003; src/sim/air.rs",
    ),
    item(
        "Contact",
        "A triangle is wet when any corner of it is under the water, and only its wet part is \
         pushed.",
        "Its wetted part is clipped by the surface and its area taken by the cross product \
         (Heron's formula loses digits on slivers).",
        "the paper §3.1–3.2, Fig. 5",
    ),
    item(
        "Smooth lens",
        "For a round pebble on flat water the pushes can be added up over its smooth shape \
         instead of its triangles, which is faster and more exact.",
        "An option for a lens over flat water (Stone panel, Forces on): the same law summed over \
         the smooth ellipsoid the mesh stands for: Gauss nodes along the wet latitudes, and around \
         each waterline arc (found exactly instead of clipped) the pressure in closed form and the \
         friction at a few nodes; the mesh then only draws it.",
        "Gauss–Legendre quadrature; docs/studies/kernel.md",
    ),
    item(
        "Paper law",
        "The faster a wet triangle moves into the water, the harder the water pushes it back.",
        "Each wetted face is pushed along its normal by ½ C_l ρ v_n² S and dragged by \
         ½ C_f ρ |V_t|² S.",
        "the paper, eqs. 11–24; Nagahiro & Hayakawa 2005",
    ),
    item(
        "Bocquet law",
        "The push grows with the whole stone's speed: the simplest rule, the one worked out by \
         hand for a flat plate.",
        "The same directions with magnitudes ½ C ρ U² S from the centre-of-mass speed U: on a \
         thin plate, Bocquet's 2D model, the analytic yardstick.",
        "Bocquet 2003, eqs. 1–3",
    ),
    item(
        "Rosellini law",
        "The push grows with the stone's speed and with how fast each part goes into the water; \
         this rule gives the best angle that experiments find.",
        "Pressure C_L ρ U max(0, v_n) S on faces advancing into the water; it alone puts the \
         minimal speed's minimum near the measured magic angle (~20°).",
        "Rosellini et al. 2005, eq. 4.2; Clanet, Hersen & Bocquet 2004",
    ),
    item(
        "Ventilated",
        "Only the front of the stone pushes on water; behind it there is a pocket of air.",
        "Only faces advancing into the water get pressure and friction; the rear sits in an \
         air-filled cavity (off: every wetted face, as printed in the paper).",
        "Clanet et al. 2004; the paper",
    ),
    item(
        "Buoyancy",
        "Water also holds up whatever is in it, a little, the deeper the more.",
        "Hydrostatic pressure ρ g d on each loaded face, d the depth of its wetted centroid: \
         Archimedes' force, exact on planar faces.",
        "Archimedes; Savitsky 1964 (buoyant lift of planing)",
    ),
    item(
        "Water's lag",
        "The water under a fast stone needs a moment to rise, and that delay helps a fast stone \
         bounce again instead of sliding.",
        "The wetted patch follows the stone's motion late by about twice the time the water \
         takes to pass under the patch. Going in, less of the stone is wet than its depth says; \
         coming out, more. That delay feeds each bounce, so a fast stone keeps skipping instead \
         of gliding, and a slow one settles into a glide and sinks. The stone touches the lake's \
         own surface (flat water or its swell), never its own rings, so a throw's skips do not \
         change with the tick, the cells or the mesh.",
        "Wagner 1932; Hewitt et al. 2011; docs/studies/wagner_lag; docs/studies/whole_throw",
    ),
    item(
        "Integrators",
        "The simulator moves the stone in tiny steps of time; steps that are too long make the \
         bounces wrong.",
        "Paper (Euler velocity, trapezoid position), symplectic Euler and RK4 take fixed ticks; \
         Adaptive flies exactly, locates contact entry by root finding and controls its error in \
         contact. A fixed step that is too long makes bounces gain energy (the app warns).",
        "the paper, eqs. 30–38; docs/studies/stability",
    ),
    item(
        "Outcome",
        "A throw ends when the stone sinks, and the app says why, from how it met the water the \
         last time.",
        "Sank when the whole underside is below the surface: too slow to skip, sank after its \
         last skip (slowed too much), dug in nose-down (tilt below zero), landed on its edge \
         (bank over 20°), or came in too steep (over 45° down). Still going at the time limit; \
         diverged when the numbers stop being finite. On the ambient water the lake is a window \
         of rings and the stone flies on past it; only with wavy contact does the lake's edge end \
         a throw (not a result).",
        "Bocquet 2003 (loss of lift); design §4",
    ),
    item(
        "A skip",
        "A skip is a bounce you can see: the stone leaves the water and flies at least its own \
         width before it lands again.",
        "A touch followed by a flight at least as long as the stone. Touches closer together \
         belong to one contact, listed in its touches column, as a person counting a throw from \
         the bank would count them.",
        "design §4; docs/studies/whole_throw",
    ),
    item(
        "Peak g",
        "Peak g says how hard the water pushed the stone up, compared with its weight.",
        "The water's largest upward push in a contact over the stone's weight (the contact \
         table's last column, the lift plot). A spun disc in Tang et al.'s tank bounced only \
         above 3.8 g; the model has no such rule, but a first contact at the slowest speed that \
         still skips peaks at 3–8 g.",
        "Tang et al. 2021; docs/studies/fidelity §12",
    ),
    item(
        "Water",
        "The lake is a grid of thin columns of water that pass water to their neighbours, so \
         rings spread out where the stone lands.",
        "Columns on a square grid joined by pipes with one signed flow each (4 or 8 pipes, \
         isotropic areas); flows first, then volumes from the new flows.",
        "O'Brien & Hodgins 1995",
    ),
    item(
        "Limiter",
        "No column can give away more water than it holds, so no water appears or vanishes.",
        "Each column's outflows are scaled so it never gives more than it holds: mass is \
         conserved exactly (the paper's clamp, eq. 41, creates water).",
        "Mei et al. 2007; the paper, eq. 41",
    ),
    item(
        "Coupling",
        "The stone pushes the water as hard as the water pushes the stone, and that push makes \
         the rings.",
        "The force the water exerts on the stone goes back to the columns under the wetted \
         triangles as pressure (Newton's third law); volume stays conserved.",
        "O'Brien & Hodgins 1995",
    ),
    item(
        "Stability",
        "The water takes its own small steps, short enough that its waves never blow up.",
        "The water steps on its own clock under the Courant limit c·Δt/l ≤ 1/√2 (4 pipes) or \
         √3/2 (8 pipes), c = √(gH), at 70 % of it.",
        "docs/studies/stability §B",
    ),
    item(
        "Wavy contact",
        "An option where the stone rides on the waves it makes itself; its results change with \
         the grid, so trust trends, not exact counts.",
        "Contact against the grid's height instead of the lake's own surface (the model the \
         presets used before the water's lag). Not converged: results move with the cell, the \
         depth and the tick (the columns are shallow-water waves; at the stone's scale real \
         water is deep).",
        "the paper (future work); docs/studies/fidelity §9–§11",
    ),
    item(
        "Receding faces",
        "A part of the stone coming out of the water is not pushed forward by it.",
        "Without ventilation the paper as printed pushes a face moving out of the water along −N \
         (energy from nowhere); read energy-consistently each face's pressure opposes its own \
         normal motion.",
        "the paper, eq. 19; physics.md §7.1",
    ),
];

/// The opening of the about panel, for a reader of fifteen: (heading, paragraph).
pub const ABOUT_OPENING: &[(&str, &str)] = &[
    (
        "Why a stone skips",
        "A skimming stone bounces because the water pushes back. Thrown flat and tilted a little, \
         front edge up, it hits the water like a water-ski: it shoves the water down and forward, \
         and the water pushes it up and back. If that push is strong enough, the stone is lifted \
         out and flies on to the next bounce, a little slower each time. Too slow, and the push \
         is too weak: the stone sinks. Too steep, coming down at more than about 45°, and it digs \
         in and goes under. Spin keeps the stone flat, like a gyroscope or a spinning top; \
         without spin it tips nose-down and dives. About 20° of tilt works best: there a stone \
         skips even when thrown slowly. That is the \"magic angle\" found in experiments.",
    ),
    (
        "Why the landing decides a throw",
        "A spinning stone is a gyroscope: a push that would tip it over turns it sideways \
         instead, slowly if it spins fast. In the air, the wind under a tilted stone lifts its \
         front edge, and that push slowly rolls a spinning stone onto its side, like a Frisbee \
         that curves away; the faster the throw and the longer the flight, the more it rolls. \
         Each touch of the water pushes up behind the centre and turns it again. So every \
         landing finds the stone a little differently placed: front edge up and nearly level, \
         and it skips on; nose down, too flat or steeply on its side, and it digs in and sinks. \
         That is why a slightly heavier stone or a slightly faster throw can make many fewer \
         skips: a few degrees at one landing decide. More spin makes each turn smaller.",
    ),
    (
        "Where the simulator still falls short",
        "In the experiments a small disc coming down as steeply as about 45° still bounces, and \
         a hard first touch lasts about a thirtieth of a second. In the simulator it bounces only \
         up to about 33°, and that touch lasts twice as long. The cause is the water's lag: the \
         water under a fast stone takes a moment to rise, and that is what lets a fast stone \
         skip again and again instead of gliding flat. But the same lag holds back the push of a \
         hard first touch. No rule for the water tried so far gets both right. In the Physics \
         panel, Shorter lag at impact and Entry lead give the first bounce the experiments \
         measured; a whole throw then ends in a long glide.",
    ),
    (
        "What the simulator does",
        "It cuts the stone into thousands of small triangles. A little at a time (a few \
         thousandths of a second, much less while the stone touches the water) it finds which \
         triangles are wet, works out how hard the water pushes on each one and how much it rubs, \
         adds all those pushes up and moves and turns the stone by that much. In the air only \
         gravity and the air act on it. The water is a grid of thin columns that pass water to \
         their neighbours, so where the stone pushes down, rings spread across the lake.",
    ),
    (
        "Why a stone skips so far on the Moon",
        "Pick the Moon in the Physics panel (World). Its gravity is a sixth of Earth's and it has \
         no air. The water pushes on the stone just as hard as on Earth, since that push comes \
         from the stone's speed, but the stone weighs six times less, so a much slower stone is \
         still thrown back up: the slowest speed that skips is about 2.5 times lower (it goes \
         with the square root of gravity). Between touches it falls six times more gently, so \
         each hop lasts six times longer and reaches six times farther, and with no air nothing \
         slows it in flight. More hops, each much longer: the stone skips far.",
    ),
    (
        "What to try",
        "Press Space to throw, then 3 for the side view. Change one thing at a time in the Launch \
         panel: slow the stone down until it no longer skips, tilt it steeply, or take its spin \
         away, and compare with the faint trails of your earlier throws. Open Experiments (X) and \
         vary Tilt from 0° to 45° to find the magic angle yourself. The presets too_slow, \
         too_steep and no_spin_dive show three ways a throw fails.",
    ),
];

/// The "about the model" panel's contents: the plain opening, then the model in detail.
pub fn about_ui(ui: &mut Ui) {
    egui::ScrollArea::vertical()
        .max_height(460.0)
        .show(ui, |ui| {
            for (heading, paragraph) in ABOUT_OPENING {
                ui.label(RichText::new(*heading).strong().size(15.0));
                ui.label(*paragraph);
                ui.add_space(6.0);
            }
            ui.separator();
            ui.label(RichText::new("The model in detail").strong().size(15.0));
            ui.weak(
                "Each part of the model in one plain sentence, then the detail, its sources in \
                 brackets.",
            );
            ui.add_space(3.0);
            for m in MODEL {
                ui.horizontal_wrapped(|ui| {
                    ui.label(RichText::new(m.topic).strong());
                    ui.label(m.plain);
                });
                ui.horizontal_wrapped(|ui| {
                    ui.weak(m.detail);
                    ui.label(RichText::new(format!("[{}]", m.sources)).italics().weak());
                });
                ui.add_space(4.0);
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn help_and_about_speak_plainly() {
        // The opening names what a skip needs, the magic angle and what to try.
        let opening: String = ABOUT_OPENING.iter().map(|(_, p)| *p).collect();
        for words in [
            "water pushes back",
            "sinks",
            "gyroscope",
            "20°",
            "magic angle",
            "triangles",
            "Moon",
            "six times",
        ] {
            assert!(opening.contains(words), "{words}");
        }
        // Section marks and issue numbers stay in the sources, never in what a student reads.
        let plain = ABOUT_OPENING
            .iter()
            .map(|(h, p)| (*h, *p))
            .chain(MODEL.iter().map(|m| (m.topic, m.plain)))
            .chain(MODEL.iter().map(|m| (m.topic, m.detail)))
            .chain(SHORTCUTS.iter().copied());
        for (topic, text) in plain {
            assert!(
                !text.contains('§') && !text.contains("issue ") && !text.contains("study"),
                "{topic}: {text}"
            );
        }
        // Issue 48: every item of the model in detail opens with one plain sentence: no
        // formula, symbol or source, short enough to read at once.
        for m in MODEL {
            let words = m.plain.split_whitespace().count();
            assert!(words <= 35, "{}: {words} words", m.topic);
            assert!(m.plain.ends_with('.'), "{}", m.topic);
            for symbol in ["=", "²", "ρ", "_", "§", "eq.", "(", "√", "Δ"] {
                assert!(
                    !m.plain.contains(symbol),
                    "{}: {symbol} in {}",
                    m.topic,
                    m.plain
                );
            }
            assert_eq!(
                m.plain.matches(". ").count(),
                0,
                "{}: one sentence",
                m.topic
            );
        }
        // Spin, the sentence a teacher needs, leads what turns the stone.
        let at = |t: &str| MODEL.iter().position(|m| m.topic == t).unwrap();
        assert!(at("Spin") < at("Rotation") && at("Spin") < at("Axial spin"));
        assert!(at("Spin") < at("Air in flight"));
        // Every key the app answers to is listed, Experiments' X included.
        assert!(SHORTCUTS.iter().any(|(k, _)| *k == "X"));
    }
}
