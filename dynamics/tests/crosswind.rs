//! A coach in a crosswind on rigid track, through the train partition (what the train FMU
//! runs): the wheel loads follow the moment balance of the instantaneous body loads
//! (closed form, `Σ F_y = F_S`, `Σ M_x = M_R`, `Σ F_z = W − F_L`) — with the ground's
//! coefficients before the deck, the deck's once the body is on it and the motion has
//! settled, and with the deck's at `U + u` under a steady gust `u` given as the FMU's
//! turbulence input.

use nalgebra::Vector3;
use std::sync::Arc;
use tbi_dynamics::solver::partitioned::TrainSide;
use tbi_dynamics::train::Speed;
use tbi_dynamics::train::{Crosswind, TrainDescription, TrainSpec};
use tbi_dynamics::vehicle::aero::{BodyLoads, VehicleAero};
use tbi_dynamics::vehicle::coach::CoachParams;

const U: f64 = 25.0;
const V: f64 = 30.0;
const RHO: f64 = 1.225;
const DECK: [f64; 2] = [40.0, 1.0e5];
/// Time for the entry and gust transients to die out, s.
const SETTLE_S: f64 = 120.0;

/// The deck's coefficients: a wind barrier halving the ground's side force and rolling
/// moment.
fn shielded() -> VehicleAero {
    let mut a = VehicleAero::default();
    a.side.iter_mut().for_each(|c| *c *= 0.5);
    a.roll.iter_mut().for_each(|c| *c *= 0.5);
    a
}

/// Σ over the coach's wheelsets of (F_y, M_x, F_z).
fn sums(side: &TrainSide) -> Vector3<f64> {
    (0..side.wheelsets.len()).map(|w| side.force(w)).sum()
}

fn check(side: &TrainSide, loads: &BodyLoads, weight: f64, when: &str) {
    let s = sums(side);
    let expected = [loads.side_n, loads.roll_nm, weight - loads.lift_n];
    let scale = [loads.side_n, loads.roll_nm, weight];
    for k in 0..3 {
        let rel = (s[k] - expected[k]).abs() / scale[k].abs();
        assert!(
            rel < 1e-4,
            "{when}: component {k} of the wheelset forces {} against the moment balance {} ({rel:.1e})",
            s[k],
            expected[k]
        );
    }
}

#[test]
fn wheel_loads_follow_the_body_loads_on_ground_deck_and_in_a_gust() {
    let params = CoachParams::xia2000();
    let res = TrainDescription {
        spec: TrainSpec::Coaches {
            params: params.clone(),
            count: 1,
        },
        speed_m_s: Speed::from_m_s(V).unwrap(),
        x0_m: 20.0,
        direction: Default::default(),
        track: 0,
        change: None,
        hunting: Default::default(),
        crosswind: Some(Crosswind {
            mean_speed_m_s: U,
            air_density_kg_m3: RHO,
            aero: VehicleAero::default(),
            on_deck: Some(shielded()),
            deck_m: Some(DECK),
            turbulent: true,
        }),
    };
    let train = res.build(0.0).unwrap();
    let still = res.spec.vehicles().unwrap()[0].model.clone();
    let weight: f64 = still.wheelsets.iter().map(|w| w.p0.z).sum();
    let centre = train.centre_offset_m(0);
    let mut side = TrainSide::new(Arc::new(train));
    let rails = vec![[Vector3::zeros(); 3]; 4];
    side.initialize(0.0, &rails);
    let ground = VehicleAero::default().loads(V, U, RHO);
    check(&side, &ground, weight, "t = 0 on the ground");
    let h = 0.005;
    let on_deck_at = (DECK[0] - (20.0 - centre)) / V;
    assert!(on_deck_at > 0.5, "the body starts on the ground");
    let mut steps = 0;
    while (steps as f64 + 1.0) * h < on_deck_at {
        side.step(h, &rails);
        steps += 1;
    }
    check(&side, &ground, weight, "just before the deck");
    // on the deck: the shielded loads, once the entry transient has died out
    for _ in 0..(SETTLE_S / h) as usize {
        side.step(h, &rails);
    }
    let deck = shielded().loads(V, U, RHO);
    assert!(deck.roll_nm < 0.6 * ground.roll_nm);
    check(&side, &deck, weight, "on the deck, settled");
    // a steady gust of 6 m/s at the body, as the wind FMU would give it
    side.body_wind[0] = 6.0;
    for _ in 0..(SETTLE_S / h) as usize {
        side.step(h, &rails);
    }
    check(
        &side,
        &shielded().loads(V, U + 6.0, RHO),
        weight,
        "in the gust, settled",
    );
}
