use stoneskip::render::{Offscreen, SceneStyle, SimulatedScene};
fn min_ms(off: &mut Offscreen, scene: &stoneskip::render::Scene, w: u32, h: u32) -> f64 {
    let mut best = f64::MAX;
    for _ in 0..6 {
        let t = std::time::Instant::now();
        off.render(scene, w, h).unwrap();
        best = best.min(t.elapsed().as_secs_f64() * 1000.0);
    }
    best
}
#[test]
fn timing() {
    let preset = stoneskip::preset::load(std::path::Path::new("assets/presets/default.ron")).unwrap();
    let state = SimulatedScene::at_time(&preset, 0.6).unwrap();
    let scene = state.scene(SceneStyle::default());
    let mut offs = Vec::new();
    for n in [2u32] {
        std::env::set_var("WATER_MESH", n.to_string());
        let mut off = Offscreen::with_samples(1).unwrap();
        off.render(&scene, 1280, 720).unwrap();
        offs.push((n, off));
    }
    let mut nogrid = scene.clone(); nogrid.water = None;
    for round in 0..2 {
        for (n, off) in offs.iter_mut() {
            eprintln!("round {round} mesh {n}x{n}: 1280: {:.1}  64: {:.1}  nogrid: {:.1}", min_ms(off, &scene, 1280, 720), min_ms(off, &scene, 64, 36), min_ms(off, &nogrid, 1280, 720));
        }
    }
}
