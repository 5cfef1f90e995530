//! Configs that cannot work are refused before any simulation, with a
//! message that names the parameter and the value; no config, however
//! wrong, makes the generator panic.

mod common;

use quakejoint_model::generator::{build, Drive};
use quakejoint_model::Config;

fn error_of(extra: &str) -> String {
    let text = format!("[record]\nfile = \"x.AT2\"\n{extra}");
    match Config::from_toml(&text, "test.toml").and_then(|c| build(&c, None, Drive::None).map(|_| ())) {
        Ok(()) => panic!("config accepted:\n{extra}"),
        Err(e) => {
            assert!(e.is_input_error(), "{e}");
            e.to_string()
        }
    }
}

fn joists(list: &[(f64, f64)]) -> String {
    let mut s = String::from("[[joint.support_beams]]\nkind = \"guide\"\ny = -7.2\n");
    for (y, a) in list {
        s += &format!("[[joint.support_beams]]\nkind = \"joist\"\ny = {y}\nangle_deg = {a}\n");
    }
    s
}

fn assert_mentions(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "message {msg:?} should mention {p:?}");
    }
}

#[test]
fn a_bearing_outside_its_center_beam_is_refused() {
    let msg = error_of(&joists(&[(7.0, 20.0)]));
    assert_mentions(&msg, &["outside the center beam", "support_beams[1]", "center_beam.length"]);
}

#[test]
fn crossing_or_coinciding_joists_are_refused() {
    let msg = error_of(&joists(&[(0.0, 10.0), (0.2, -10.0)]));
    assert_mentions(&msg, &["support_beams[1] and [2] cross", "x = 0.5"]);
    let msg = error_of(&joists(&[(1.0, 13.0), (1.0, 13.0)]));
    assert_mentions(&msg, &["same line"]);
}

#[test]
fn non_positive_dimensions_and_masses_are_refused() {
    assert_mentions(&error_of("[joint]\npitch = 0.0\n"), &["joint.pitch = 0", "must be within 0.02 <= x <= 1 m"]);
    assert_mentions(&error_of("[joint]\npitch = -0.1\n"), &["joint.pitch = -0.1"]);
    assert_mentions(&error_of("[joint.center_beam]\nlength = -15.0\n"), &["joint.center_beam.length = -15"]);
    assert_mentions(&error_of("[joint.bearing]\nmass = 0.0\n"), &["joint.bearing.mass = 0"]);
    assert_mentions(&error_of("[joint.support_beam]\nmass = -600.0\n"), &["joint.support_beam.mass = -600"]);
    assert_mentions(&error_of("[bridge]\nmass = 0.0\n"), &["bridge.mass = 0"]);
    assert_mentions(&error_of("[joint]\ncenter_beams = 0\n"), &["joint.center_beams = 0"]);
    assert_mentions(&error_of("[joint.center_beam]\nwidth = 0.13\n"), &["width", "pitch"]);
}

#[test]
fn physically_absurd_values_are_refused_naming_the_field() {
    // values that used to end deep in the solver as `non-finite value`
    for (extra, field) in [
        ("[joint.friction]\nnormal_force = 1e300\n", "joint.friction.normal_force = 1e300"),
        ("[joint.friction]\nv_eps = 1e-300\n", "joint.friction.v_eps = 1e-300"),
        ("[joint.bearing]\nmass = 9e18\n", "joint.bearing.mass = 9e18"),
        ("[simulation]\nduration = 1e-300\n", "simulation.duration = 1e-300"),
        ("[joint.bushing]\nkx = 1e25\n", "joint.bushing.kx = 1e25"),
        ("[bridge]\nmass = 1e30\n", "bridge.mass = 1e30"),
        ("[joint.friction]\nmu = 50.0\n", "joint.friction.mu = 50"),
    ] {
        assert_mentions(&error_of(extra), &[field, "must be within"]);
    }
}

#[test]
fn angles_at_or_beyond_ninety_degrees_are_refused() {
    assert_mentions(&error_of(&joists(&[(0.0, 90.0)])), &["support_beams[1].angle_deg = 90", "-90 < x < 90 deg"]);
    assert_mentions(&error_of(&joists(&[(0.0, -95.0)])), &["angle_deg = -95"]);
    let guide = "[[joint.support_beams]]\nkind = \"guide\"\ny = -7.2\nangle_deg = 5.0\n";
    assert_mentions(&error_of(guide), &["a guide runs parallel"]);
}

#[test]
fn an_empty_support_beam_list_is_refused() {
    assert_mentions(&error_of("[joint]\nsupport_beams = []\n"), &["joint.support_beams", "empty"]);
}

#[test]
fn unknown_keys_and_wrong_types_name_the_key() {
    assert_mentions(&error_of("[joint]\npich = 0.1\n"), &["unknown field `pich`", "test.toml"]);
    assert_mentions(&error_of("[joint.friction]\nmu = \"high\"\n"), &["mu", "test.toml"]);
    assert_mentions(&error_of("[bridge]\ndamping = 1.0\n"), &["bridge.damping = 1"]);
    assert_mentions(&error_of("[bridge]\nw0 = 6.3\nperiod = 1.0\n"), &["either bridge.w0 or bridge.period"]);
    assert_mentions(&error_of("[joint.friction]\nv_eps = 0.0\n"), &["joint.friction.v_eps = 0"]);
}

/// Deterministic pseudo-random numbers.
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn no_config_makes_the_generator_panic() {
    // Mutate one to three fields of a valid config at a time, to values that
    // are ordinary, extreme, zero, negative, NaN or infinite.
    let specials = [0.0, -1.0, 1e300, -1e-300, f64::NAN, f64::INFINITY, 1e-9, 89.999, 90.0, 7.5];
    let mut seed = 42u64;
    let (mut built, mut refused) = (0, 0);
    for _ in 0..600 {
        let mut c = Config::default();
        c.joint.center_beams = 3;
        for _ in 0..1 + (lcg(&mut seed) * 3.0) as usize {
            let r = lcg(&mut seed);
            let value = |seed: &mut u64, normal: f64| -> f64 {
                if lcg(seed) < 0.4 {
                    specials[(lcg(seed) * specials.len() as f64) as usize % specials.len()]
                } else {
                    normal * (0.5 + lcg(seed))
                }
            };
            match (r * 10.0) as usize {
                0 => c.joint.pitch = value(&mut seed, 0.13),
                1 => c.joint.center_beam.length = value(&mut seed, 15.0),
                2 => c.joint.center_beam.width = value(&mut seed, 0.09),
                3 => c.joint.bearing.mass = value(&mut seed, 20.0),
                4 => c.joint.bushing.kx = value(&mut seed, 1e7),
                5 => c.joint.friction.v_eps = value(&mut seed, 1e-3),
                6 => c.bridge.damping = value(&mut seed, 0.05),
                7 => c.joint.center_beams = (lcg(&mut seed) * 5.0) as usize,
                8 => {
                    let k = (lcg(&mut seed) * c.joint.support_beams.len() as f64) as usize;
                    c.joint.support_beams[k].y = value(&mut seed, 3.0);
                }
                _ => {
                    let k = (lcg(&mut seed) * c.joint.support_beams.len() as f64) as usize;
                    c.joint.support_beams[k].angle_deg = value(&mut seed, 15.0);
                }
            }
        }
        match build(&c, None, Drive::None) {
            Ok(model) => {
                // what the generator accepts, the solver accepts too
                quakejoint_solver::Assembly::new(&model.system, &Default::default()).expect("solver accepts");
                built += 1;
            }
            Err(e) => {
                assert!(e.is_input_error() && !e.to_string().is_empty());
                refused += 1;
            }
        }
    }
    assert!(built > 50 && refused > 50, "accepted {built}, refused {refused}");
}
