//! In-process test participants for the coupling algorithms: linear structural subsystems
//! `M ü + C u̇ + K u = f(t) + inputs`, each integrated by Newmark's average acceleration rule
//! (β = 1/4, γ = 1/2) inside `do_step`, with inputs taken as values at the end of the step.
//!
//! A [`Case`] is a "bridge" (participant 0) and a "train" (participant 1) joined by contact
//! springs ("wheels") of stiffness `kc` between a train DOF and a bridge DOF. The bridge
//! receives the contact forces `kc (u_train − u_bridge)` as input forces and outputs the
//! displacements of its contact DOFs; the train receives those displacements and contains the
//! springs. [`Case::monolithic`] integrates the assembled system with the same Newmark rule, so
//! a converged implicit co-simulation must reproduce it to the coupling tolerance.
#![allow(dead_code)]

use std::cell::RefCell;
use std::rc::Rc;

use tbi_coupling::{
    advance, Connection, CouplingError, CouplingScheme, CouplingStatistics, OnNonConvergence,
    Participant, StepStatus, System,
};

pub type Mat = Vec<Vec<f64>>;

/// Value reference of the first output of a participant.
pub const OUT: u32 = 100;
/// Value reference of the displacement of DOF 0 (DOF i: `DOF + i`), for recording.
pub const DOF: u32 = 200;

pub fn zeros(n: usize) -> Mat {
    vec![vec![0.0; n]; n]
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting.
pub fn solve(a: &Mat, b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut a = a.clone();
    let mut x = b.to_vec();
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap();
        a.swap(col, piv);
        x.swap(col, piv);
        assert!(a[col][col] != 0.0, "singular matrix");
        for row in col + 1..n {
            let f = a[row][col] / a[col][col];
            if f != 0.0 {
                let (upper, lower) = a.split_at_mut(row);
                for (r, &p) in lower[0][col..].iter_mut().zip(&upper[col][col..]) {
                    *r -= f * p;
                }
                x[row] -= f * x[col];
            }
        }
    }
    for row in (0..n).rev() {
        let s: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (x[row] - s) / a[row][row];
    }
    x
}

fn matvec(a: &Mat, x: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|row| row.iter().zip(x).map(|(a, x)| a * x).sum())
        .collect()
}

/// `f_dof(t) = amplitude · sin(omega t)` (N); zero at t = 0 so that systems at rest start with
/// zero acceleration.
#[derive(Debug, Clone, Copy)]
pub struct Load {
    pub dof: usize,
    pub amplitude: f64,
    pub omega: f64,
}

/// A linear structure `M ü + C u̇ + K u = f(t)`.
#[derive(Debug, Clone)]
pub struct Structure {
    pub m: Mat,
    pub c: Mat,
    pub k: Mat,
    pub loads: Vec<Load>,
}

impl Structure {
    pub fn n(&self) -> usize {
        self.m.len()
    }

    pub fn load(&self, t: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.n()];
        for l in &self.loads {
            f[l.dof] += l.amplitude * (l.omega * t).sin();
        }
        f
    }

    /// A chain of `masses` joined by springs `k` and dampers `c`, with springs `k_end` and
    /// dampers `c` from both ends to the ground.
    pub fn chain(masses: &[f64], k: f64, k_end: f64, c: f64) -> Self {
        let n = masses.len();
        let (mut mm, mut kk, mut cc) = (zeros(n), zeros(n), zeros(n));
        for i in 0..n {
            mm[i][i] = masses[i];
        }
        let mut spring = |a: usize, b: Option<usize>, k: f64, c: f64| {
            kk[a][a] += k;
            cc[a][a] += c;
            if let Some(b) = b {
                kk[b][b] += k;
                kk[a][b] -= k;
                kk[b][a] -= k;
                cc[b][b] += c;
                cc[a][b] -= c;
                cc[b][a] -= c;
            }
        };
        for i in 0..n.saturating_sub(1) {
            spring(i, Some(i + 1), k, c);
        }
        spring(0, None, k_end, c);
        spring(n - 1, None, k_end, c);
        Structure {
            m: mm,
            c: cc,
            k: kk,
            loads: Vec::new(),
        }
    }

    /// Newmark's effective stiffness `K + 2/h C + 4/h² M` plus `extra`.
    pub fn effective(&self, h: f64, extra: &Mat) -> Mat {
        let n = self.n();
        let mut a = zeros(n);
        for i in 0..n {
            for j in 0..n {
                a[i][j] = self.k[i][j]
                    + 2.0 / h * self.c[i][j]
                    + 4.0 / (h * h) * self.m[i][j]
                    + extra[i][j];
            }
        }
        a
    }

    /// A train of `n` DOFs: wheels `0..nw` (masses 1.5 t + 0.3 t per index) each hung from the
    /// body `body_of(j) ≥ nw` by a suspension of 4e6 N/m and 6e4 N s/m; the bodies' masses
    /// and the loads are left to the caller.
    pub fn wheels_under_bodies(nw: usize, n: usize, body_of: impl Fn(usize) -> usize) -> Self {
        let (ks, cs) = (4.0e6, 6.0e4);
        let mut train = Structure {
            m: zeros(n),
            c: zeros(n),
            k: zeros(n),
            loads: Vec::new(),
        };
        for j in 0..nw {
            let body = body_of(j);
            train.m[j][j] = 1.5e3 + 300.0 * j as f64;
            for (mat, v) in [(&mut train.k, ks), (&mut train.c, cs)] {
                mat[j][j] += v;
                mat[body][body] += v;
                mat[j][body] -= v;
                mat[body][j] -= v;
            }
        }
        train
    }
}

/// Displacement, velocity, acceleration.
#[derive(Debug, Clone, PartialEq)]
pub struct Kinematics {
    pub u: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

impl Kinematics {
    pub fn rest(n: usize) -> Self {
        Self {
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        }
    }
}

/// One Newmark average-acceleration step of `M ü + C u̇ + (K + k_extra) u = f_next` to the end
/// of the step.
pub fn newmark(
    s: &Structure,
    k_extra: &Mat,
    f_next: &[f64],
    st: &Kinematics,
    h: f64,
) -> Kinematics {
    let n = s.n();
    let mu: Vec<f64> = (0..n)
        .map(|i| 4.0 / (h * h) * st.u[i] + 4.0 / h * st.v[i] + st.a[i])
        .collect();
    let cu: Vec<f64> = (0..n).map(|i| 2.0 / h * st.u[i] + st.v[i]).collect();
    let (mm, cc) = (matvec(&s.m, &mu), matvec(&s.c, &cu));
    let rhs: Vec<f64> = (0..n).map(|i| f_next[i] + mm[i] + cc[i]).collect();
    let u = solve(&s.effective(h, k_extra), &rhs);
    let a: Vec<f64> = (0..n)
        .map(|i| 4.0 / (h * h) * (u[i] - st.u[i]) - 4.0 / h * st.v[i] - st.a[i])
        .collect();
    let v: Vec<f64> = (0..n)
        .map(|i| st.v[i] + 0.5 * h * (st.a[i] + a[i]))
        .collect();
    Kinematics { u, v, a }
}

/// Calls seen by a participant.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Probe {
    pub steps: usize,
    pub saves: usize,
    pub restores: usize,
}

/// What an output value reference returns.
#[derive(Debug, Clone, Copy)]
pub enum Out {
    /// Displacement of a DOF (m).
    Displacement(usize),
    /// Force `kc (u_dof − z)` of contact spring `j` on the body at its far end (N).
    SpringForce(usize),
}

/// A [`Structure`] as a co-simulation participant.
///
/// Inputs: vr `j < force_dofs.len()` is a force (N) on DOF `force_dofs[j]`; the following
/// `springs.len()` vrs are the far-end displacements `z` (m) of springs `(dof, kc)`. Outputs:
/// vr `OUT + j` is `outputs[j]`; vr `DOF + i` is the displacement of DOF `i`.
pub struct Sub {
    name: String,
    s: Structure,
    force_dofs: Vec<usize>,
    springs: Vec<(usize, f64)>,
    outputs: Vec<Out>,
    t: f64,
    state: Kinematics,
    inputs: Vec<f64>,
    saved: Option<(f64, Kinematics, Vec<f64>)>,
    probe: Rc<RefCell<Probe>>,
    /// Test hook: `restore_state` does nothing (to show that rollback matters).
    pub broken_restore: bool,
}

impl Sub {
    pub fn new(
        name: &str,
        s: Structure,
        force_dofs: Vec<usize>,
        springs: Vec<(usize, f64)>,
        outputs: Vec<Out>,
    ) -> (Self, Rc<RefCell<Probe>>) {
        let probe = Rc::new(RefCell::new(Probe::default()));
        let n = s.n();
        let ni = force_dofs.len() + springs.len();
        let sub = Sub {
            name: name.to_owned(),
            s,
            force_dofs,
            springs,
            outputs,
            t: 0.0,
            state: Kinematics::rest(n),
            inputs: vec![0.0; ni],
            saved: None,
            probe: probe.clone(),
            broken_restore: false,
        };
        (sub, probe)
    }

    fn spring_z(&self, j: usize) -> f64 {
        self.inputs[self.force_dofs.len() + j]
    }
}

impl Participant for Sub {
    fn name(&self) -> &str {
        &self.name
    }

    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError> {
        for (&vr, &v) in vrs.iter().zip(values) {
            let slot = self
                .inputs
                .get_mut(vr as usize)
                .ok_or_else(|| CouplingError::new(format!("{}: no input vr {vr}", self.name)))?;
            *slot = v;
        }
        Ok(())
    }

    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError> {
        for (&vr, out) in vrs.iter().zip(values.iter_mut()) {
            *out = if vr >= DOF {
                self.state.u[(vr - DOF) as usize]
            } else {
                match self.outputs.get((vr - OUT) as usize) {
                    Some(Out::Displacement(i)) => self.state.u[*i],
                    Some(Out::SpringForce(j)) => {
                        let (dof, kc) = self.springs[*j];
                        kc * (self.state.u[dof] - self.spring_z(*j))
                    }
                    None => {
                        return Err(CouplingError::new(format!(
                            "{}: no output vr {vr}",
                            self.name
                        )))
                    }
                }
            };
        }
        Ok(())
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError> {
        if (t - self.t).abs() > 1e-9 * h {
            return Err(CouplingError::new(format!(
                "{}: do_step at t = {t} but the model is at {}",
                self.name, self.t
            )));
        }
        self.probe.borrow_mut().steps += 1;
        let n = self.s.n();
        let mut f = self.s.load(t + h);
        for (j, &dof) in self.force_dofs.iter().enumerate() {
            f[dof] += self.inputs[j];
        }
        let mut k_extra = zeros(n);
        for (j, &(dof, kc)) in self.springs.iter().enumerate() {
            k_extra[dof][dof] += kc;
            f[dof] += kc * self.spring_z(j);
        }
        self.state = newmark(&self.s, &k_extra, &f, &self.state, h);
        self.t = t + h;
        Ok(StepStatus::Ok)
    }

    fn save_state(&mut self) -> Result<(), CouplingError> {
        self.probe.borrow_mut().saves += 1;
        self.saved = Some((self.t, self.state.clone(), self.inputs.clone()));
        Ok(())
    }

    fn restore_state(&mut self) -> Result<(), CouplingError> {
        self.probe.borrow_mut().restores += 1;
        if self.broken_restore {
            return Ok(());
        }
        let (t, state, inputs) = self
            .saved
            .clone()
            .ok_or_else(|| CouplingError::new(format!("{}: no saved state", self.name)))?;
        self.t = t;
        self.state = state;
        self.inputs = inputs;
        Ok(())
    }
}

/// Wraps a participant and answers `do_step` with [`StepStatus::Discard`] (without stepping)
/// whenever `h > max_h`.
pub struct Discarding {
    pub inner: Box<dyn Participant>,
    pub max_h: f64,
    pub discards: Rc<RefCell<usize>>,
}

impl Participant for Discarding {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError> {
        self.inner.set_real(vrs, values)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError> {
        self.inner.get_real(vrs, values)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError> {
        if h > self.max_h {
            *self.discards.borrow_mut() += 1;
            return Ok(StepStatus::Discard);
        }
        self.inner.do_step(t, h)
    }
    fn save_state(&mut self) -> Result<(), CouplingError> {
        self.inner.save_state()
    }
    fn restore_state(&mut self) -> Result<(), CouplingError> {
        self.inner.restore_state()
    }
}

/// Contact spring between train DOF `train_dof` and bridge DOF `bridge_dof`.
#[derive(Debug, Clone, Copy)]
pub struct Wheel {
    pub bridge_dof: usize,
    pub train_dof: usize,
    /// Contact stiffness (N/m).
    pub kc: f64,
}

/// Bridge (participant 0) and train (participant 1).
#[derive(Debug, Clone)]
pub struct Case {
    pub bridge: Structure,
    pub train: Structure,
    pub wheels: Vec<Wheel>,
}

/// The run of a co-simulation: displacements of all DOFs (bridge then train) after every macro
/// step, and the statistics.
pub struct Run {
    pub u: Vec<Vec<f64>>,
    pub stats: CouplingStatistics,
    pub probes: [Rc<RefCell<Probe>>; 2],
    /// Sizes of all kept (sub)steps, in order.
    pub hs: Vec<f64>,
    /// For each macro step, the number of kept substeps up to its end.
    pub ends: Vec<usize>,
}

impl Case {
    /// Two single-DOF oscillators (bridge ω ≈ 10 rad/s, train ω ≈ 10 rad/s) joined by a soft
    /// contact spring: weak coupling, for which explicit schemes are stable and accurate.
    pub fn two_oscillators() -> Self {
        let bridge = Structure {
            m: vec![vec![1.0]],
            c: vec![vec![0.1]],
            k: vec![vec![100.0]],
            loads: vec![Load {
                dof: 0,
                amplitude: 1.0,
                omega: 3.0,
            }],
        };
        let train = Structure {
            m: vec![vec![0.5]],
            c: vec![vec![0.05]],
            k: vec![vec![50.0]],
            loads: vec![Load {
                dof: 0,
                amplitude: 2.0,
                omega: 7.0,
            }],
        };
        Case {
            bridge,
            train,
            wheels: vec![Wheel {
                bridge_dof: 0,
                train_dof: 0,
                kc: 20.0,
            }],
        }
    }

    /// Track-like case with `nw` wheels: a bridge chain of two heavy end masses (2e4 kg)
    /// around `nw` light rail masses (about `m_rail` kg, the contact DOFs), and a train of `nw`
    /// wheel masses under one car body; contact stiffness about `kc` (N/m), varying per wheel.
    /// Forces are ~1e5 N, displacements ~1e-2 m.
    pub fn track(nw: usize, m_rail: f64, kc: f64) -> Self {
        let mut masses = vec![2.0e4];
        masses.extend((0..nw).map(|j| m_rail * (1.0 + 0.5 * j as f64)));
        masses.push(2.0e4);
        let mut bridge = Structure::chain(&masses, 4.0e8, 2.0e8, 2.0e4);
        bridge.loads.push(Load {
            dof: 0,
            amplitude: 5.0e4,
            omega: 40.0,
        });
        // Train: wheels 0..nw under one body nw.
        let mut train = Structure::wheels_under_bodies(nw, nw + 1, |_| nw);
        train.m[nw][nw] = 2.0e4 * nw as f64;
        train.loads.push(Load {
            dof: nw,
            amplitude: 1.0e5 * nw as f64,
            omega: 25.0,
        });
        train.loads.push(Load {
            dof: 0,
            amplitude: 3.0e4,
            omega: 90.0,
        });
        let wheels = (0..nw)
            .map(|j| Wheel {
                bridge_dof: 1 + j,
                train_dof: j,
                kc: kc / (1.0 + j as f64),
            })
            .collect();
        Case {
            bridge,
            train,
            wheels,
        }
    }

    pub fn dofs(&self) -> usize {
        self.bridge.n() + self.train.n()
    }

    /// The two participants with probes, and the connections: bridge displacements → train
    /// (forward), train contact forces → bridge (feedback).
    pub fn system(&self) -> (System, [Rc<RefCell<Probe>>; 2]) {
        self.system_with(false)
    }

    /// [`Case::system`] with participants whose `restore_state` does nothing when
    /// `broken_restore`.
    pub fn system_with(&self, broken_restore: bool) -> (System, [Rc<RefCell<Probe>>; 2]) {
        let nw = self.wheels.len();
        let (mut bridge, pb) = Sub::new(
            "bridge",
            self.bridge.clone(),
            self.wheels.iter().map(|w| w.bridge_dof).collect(),
            Vec::new(),
            self.wheels
                .iter()
                .map(|w| Out::Displacement(w.bridge_dof))
                .collect(),
        );
        let (mut train, pt) = Sub::new(
            "train",
            self.train.clone(),
            Vec::new(),
            self.wheels.iter().map(|w| (w.train_dof, w.kc)).collect(),
            (0..nw).map(Out::SpringForce).collect(),
        );
        bridge.broken_restore = broken_restore;
        train.broken_restore = broken_restore;
        let mut connections = Vec::new();
        for j in 0..nw as u32 {
            connections.push(Connection {
                from: 0,
                from_vr: OUT + j,
                to: 1,
                to_vr: j,
            });
            connections.push(Connection {
                from: 1,
                from_vr: OUT + j,
                to: 0,
                to_vr: j,
            });
        }
        let sys = System::new(vec![Box::new(bridge), Box::new(train)], connections);
        (sys, [pb, pt])
    }

    /// The assembled (monolithic) system: bridge DOFs, then train DOFs.
    pub fn assembled(&self) -> Structure {
        let (nb, n) = (self.bridge.n(), self.dofs());
        let mut s = Structure {
            m: zeros(n),
            c: zeros(n),
            k: zeros(n),
            loads: Vec::new(),
        };
        for (src, off) in [(&self.bridge, 0), (&self.train, nb)] {
            for i in 0..src.n() {
                for j in 0..src.n() {
                    s.m[off + i][off + j] = src.m[i][j];
                    s.c[off + i][off + j] = src.c[i][j];
                    s.k[off + i][off + j] = src.k[i][j];
                }
            }
            s.loads.extend(src.loads.iter().map(|l| Load {
                dof: l.dof + off,
                ..*l
            }));
        }
        for w in &self.wheels {
            let (b, t) = (w.bridge_dof, nb + w.train_dof);
            s.k[b][b] += w.kc;
            s.k[t][t] += w.kc;
            s.k[b][t] -= w.kc;
            s.k[t][b] -= w.kc;
        }
        s
    }

    /// Monolithic Newmark solution with steps `hs` from rest at t = 0: displacements after each
    /// step.
    pub fn monolithic(&self, hs: &[f64]) -> Vec<Vec<f64>> {
        let s = self.assembled();
        let none = zeros(s.n());
        let mut st = Kinematics::rest(s.n());
        let mut t = 0.0;
        let mut out = Vec::new();
        for &h in hs {
            st = newmark(&s, &none, &s.load(t + h), &st, h);
            t += h;
            out.push(st.u.clone());
        }
        out
    }

    /// The monolithic solution with the (sub)steps of `run`, at the ends of its macro steps.
    pub fn monolithic_like(&self, run: &Run) -> Vec<Vec<f64>> {
        let all = self.monolithic(&run.hs);
        run.ends.iter().map(|&e| all[e - 1].clone()).collect()
    }

    /// The Jacobian `H' = −(Kc⁻¹ + G_T)⁻¹ G_B` of the interface map of the implicit scheme
    /// (contact forces → contact forces), with `G` the contact compliances of Newmark's
    /// effective stiffness at step `h`.
    pub fn interface_jacobian(&self, h: f64) -> Mat {
        let nw = self.wheels.len();
        let compliance = |s: &Structure, dofs: Vec<usize>| -> Mat {
            let keff = s.effective(h, &zeros(s.n()));
            let mut g = zeros(nw);
            for (j, &dj) in dofs.iter().enumerate() {
                let mut e = vec![0.0; s.n()];
                e[dj] = 1.0;
                let col = solve(&keff, &e);
                for (i, &di) in dofs.iter().enumerate() {
                    g[i][j] = col[di];
                }
            }
            g
        };
        let gb = compliance(
            &self.bridge,
            self.wheels.iter().map(|w| w.bridge_dof).collect(),
        );
        let mut a = compliance(
            &self.train,
            self.wheels.iter().map(|w| w.train_dof).collect(),
        );
        for (j, w) in self.wheels.iter().enumerate() {
            a[j][j] += 1.0 / w.kc;
        }
        // H' = −A⁻¹ G_B, column by column.
        let mut hp = zeros(nw);
        for j in 0..nw {
            let col: Vec<f64> = (0..nw).map(|i| gb[i][j]).collect();
            let x = solve(&a, &col);
            for i in 0..nw {
                hp[i][j] = -x[i];
            }
        }
        hp
    }

    /// Runs `steps` macro steps of size `h` from rest with `scheme` and `policy`.
    pub fn run(
        &self,
        scheme: &mut dyn CouplingScheme,
        h: f64,
        steps: usize,
        policy: OnNonConvergence,
    ) -> Result<Run, CouplingError> {
        self.run_system(self.system(), scheme, h, steps, policy)
    }

    pub fn run_system(
        &self,
        (mut sys, probes): (System, [Rc<RefCell<Probe>>; 2]),
        scheme: &mut dyn CouplingScheme,
        h: f64,
        steps: usize,
        policy: OnNonConvergence,
    ) -> Result<Run, CouplingError> {
        scheme.initialize(&mut sys)?;
        let mut stats = CouplingStatistics::new();
        let mut u = Vec::new();
        let (mut hs, mut ends) = (Vec::new(), Vec::new());
        let dofs: Vec<u32> = (0..self.bridge.n() as u32).map(|i| DOF + i).collect();
        let tdofs: Vec<u32> = (0..self.train.n() as u32).map(|i| DOF + i).collect();
        for k in 0..steps {
            let report = advance(scheme, &mut sys, k as f64 * h, h, policy)?;
            stats.record(&report);
            hs.extend(report.steps.iter().map(|s| s.h));
            ends.push(hs.len());
            let mut ub = vec![0.0; dofs.len()];
            let mut ut = vec![0.0; tdofs.len()];
            sys.participants[0].get_real(&dofs, &mut ub)?;
            sys.participants[1].get_real(&tdofs, &mut ut)?;
            ub.extend(ut);
            u.push(ub);
        }
        Ok(Run {
            u,
            stats,
            probes,
            hs,
            ends,
        })
    }
}

/// Spectral radius by power iteration (for matrices with a dominant real eigenvalue, as
/// `H'` has: it is minus the product of two symmetric positive definite matrices).
pub fn spectral_radius(a: &Mat) -> f64 {
    let mut v = vec![1.0; a.len()];
    let mut rho = 0.0;
    for _ in 0..10_000 {
        let w = matvec(a, &v);
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        v = w.iter().map(|x| x / norm).collect();
        if (norm - rho).abs() <= 1e-14 * norm {
            break;
        }
        rho = norm;
    }
    rho
}

/// `max |a − b| / max |b|` over all entries of two trajectories.
pub fn relative_error(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut num: f64 = 0.0;
    let mut den: f64 = 0.0;
    for (ra, rb) in a.iter().zip(b) {
        for (x, y) in ra.iter().zip(rb) {
            num = num.max((x - y).abs());
            den = den.max(y.abs());
        }
    }
    num / den
}
