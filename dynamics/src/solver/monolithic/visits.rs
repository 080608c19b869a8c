//! Which wheelsets and vehicles a step visits: on the deck of an ideal track the wheelsets
//! whose step would change nothing are left out (idle), so that a long train that has not
//! reached the bridge yet, or an HSLM train on a short span with most of its axles off the
//! deck, costs a step only what its wheelsets near the deck do.

use super::geometry::{Geometry, Placement};
use crate::train::WheelsetRef;

/// The wheelsets the step to the geometry `geo` (its positions made) has to visit, ascending,
/// into `busy`; `rest` (per vehicle, its last step left it as it was) kept only for the
/// vehicles still off the deck.
///
/// With `idle_allowed` (the ideal track, at this step and at the one before), a wheelset
/// that is off the deck at `t` and was so at the step before is left out (idle) when it is a
/// moving force (`inert`: zero shapes, zero rail motion and its constant force already) or
/// when its vehicle is at rest there: the vehicle's last step, off the deck and without wind
/// on the train, left its state bit for bit as it was, so this step, with the same inputs,
/// would too. Every other wheelset is busy. `first_ws`: each vehicle's first wheelset.
pub(super) fn busy_wheelsets(
    m: &Placement<'_>,
    geo: &Geometry,
    first_ws: &[usize],
    inert: &[bool],
    idle_allowed: bool,
    rest: &mut [bool],
    busy: &mut Vec<usize>,
) {
    // the vehicles at rest stay so while they stay off the deck (one that does not is
    // stepped, which tells anew)
    for (i, tv) in m.train.vehicles.iter().enumerate() {
        let f0 = first_ws[i];
        rest[i] = rest[i]
            && idle_allowed
            && (f0..f0 + tv.model.wheelsets.len())
                .all(|w| !geo.on[w] && !m.bridge.on_deck(geo.x[w]));
    }
    busy.clear();
    for (w, ws) in m.wheelsets.iter().enumerate() {
        let x = geo.x[w];
        if idle_allowed && !geo.on[w] && !m.bridge.on_deck(x) && (inert[w] || rest[ws.vehicle]) {
            continue;
        }
        busy.push(w);
    }
}

/// The vehicles of the `busy` wheelsets and those without wheelsets (`loose`, ascending),
/// ascending, into `vehicles`.
pub(super) fn busy_vehicles(
    busy: &[usize],
    wheelsets: &[WheelsetRef],
    loose: &[usize],
    vehicles: &mut Vec<usize>,
) {
    vehicles.clear();
    let mut loose = loose.iter().copied().peekable();
    for &ws in busy.iter() {
        let v = wheelsets[ws].vehicle;
        vehicles.extend(std::iter::from_fn(|| loose.next_if(|&l| l < v)));
        if vehicles.last() != Some(&v) {
            vehicles.push(v);
        }
    }
    vehicles.extend(loose);
}
