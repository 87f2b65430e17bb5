//! The second core: a helper thread that takes half of each step's heavy work (the spring pass
//! and half the element pass, half the Rayleigh viscosity's, and half the spring blocks of CG's
//! product `A x`).
//!
//! Results never depend on whether the helper runs: without it (one core, or
//! `Simulation::set_threads(1)`) the main thread does the helper's share itself, on the same
//! buffers and in the same order, so the sums are the same bit for bit (`crates/softgrip-core/tests/threads.rs`).
//! Hand-offs are atomic counters and spin-waits, and a posted job is claimed by whichever
//! thread gets to it first; why: `docs/design/second-core.md`.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock, RwLock, RwLockReadGuard, RwLockWriteGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use glam::DVec3;

use crate::model::Model;
use crate::solver::System;
use crate::solver::cg::LinearOperator;
use crate::state::State;
use crate::step::assemble::{HELPER, Share, Stage, StageScratch};

const ASSEMBLE: u64 = 1;
const PRODUCT: u64 = 2;

/// Spins of the idle helper before it starts yielding its core between
/// looks at the job (~20 us).
const IDLE_SPINS: u32 = 20_000;

/// How long the helper spins for the next job before it parks.
const SPIN_TIME: Duration = Duration::from_millis(5);

/// Helper threads running in this process ...
static HELPERS: AtomicUsize = AtomicUsize::new(0);
/// ... and simulations with a work split (each one main thread, stepping or
/// about to). A helper is started only while the two together leave a core
/// free: more simulations at once (a sweep, a fit's probes, parallel tests)
/// run on their own threads, with the same results.
static RUNNING: AtomicUsize = AtomicUsize::new(0);

/// A cap on [`cores`] set by [`limit_cores`] (0 = none).
static CORE_CAP: AtomicUsize = AtomicUsize::new(0);

/// The cores this process may use: the machine's, read once
/// (`available_parallelism` reads the affinity mask and cgroup files, which
/// a simulation looking every few steps must not do again), or fewer after
/// [`limit_cores`].
pub fn cores() -> usize {
    static CORES: OnceLock<usize> = OnceLock::new();
    let machine = *CORES.get_or_init(|| thread::available_parallelism().map_or(1, |n| n.get()));
    match CORE_CAP.load(Ordering::Relaxed) {
        0 => machine,
        cap => cap.min(machine),
    }
}

/// Lets this process's simulations use at most `n` cores in all (0 lifts the
/// cap). For a process that is one of several on a machine, each given its
/// share by a scheduler that does not pin it (a Ray task with `num_cpus=1`):
/// without the cap each would start a helper on a core another one runs on,
/// and the spin-waits of both would take turns. The results do not change.
pub fn limit_cores(n: usize) {
    CORE_CAP.store(n, Ordering::Relaxed);
}

/// Simulations with a work split alive in this process now (each one
/// main thread, stepping or about to).
pub fn running() -> usize {
    RUNNING.load(Ordering::SeqCst)
}

/// Takes one helper slot if the machine has a core to spare.
fn reserve_helper() -> bool {
    let running = RUNNING.load(Ordering::SeqCst);
    HELPERS
        .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |h| {
            (h + running < cores()).then_some(h + 1)
        })
        .is_ok()
}

/// Whether a simulation without a helper would get one now ...
pub fn helper_available() -> bool {
    HELPERS.load(Ordering::SeqCst) + RUNNING.load(Ordering::SeqCst) < cores()
}

/// ... and whether one with a helper should give it up: the main threads
/// and helpers running now are more than the cores (another simulation
/// started since), and a helper then only competes for a core.
pub fn oversubscribed() -> bool {
    HELPERS.load(Ordering::SeqCst) + RUNNING.load(Ordering::SeqCst) > cores()
}

/// The helper's share of the force passes.
#[derive(Debug, Default)]
struct AssemblyShare {
    /// Positions and velocities of the step (the rest of it is unused).
    state: State,
    force: Vec<DVec3>,
    system: System,
    /// The helper's stage timings since the last [`Parallel::finish_assembly`].
    stages: StageScratch,
}

/// The helper's half of a product `A x`.
#[derive(Debug, Default)]
struct ProductShare {
    x: Vec<DVec3>,
    y: Vec<DVec3>,
}

#[derive(Debug)]
struct Shared {
    model: Arc<Model>,
    /// `(sequence << 2) | kind` of the last job posted ...
    job: AtomicU64,
    /// ... of the last one claimed (by the helper or, taken back, by the
    /// main thread) ...
    claimed: AtomicU64,
    /// ... and of the last one the helper finished.
    done: AtomicU64,
    stop: AtomicBool,
    sleeping: AtomicBool,
    /// The main thread's system; the helper reads it during products.
    system: RwLock<System>,
    assembly: Mutex<AssemblyShare>,
    product: Mutex<ProductShare>,
}

/// A lock that a panicked thread left poisoned still holds valid buffers
/// (they are rebuilt every step), so take it anyway.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// The split of one simulation's work between the main thread and a helper.
#[derive(Debug)]
pub struct Parallel {
    shared: Arc<Shared>,
    helper: Option<JoinHandle<()>>,
}

impl Parallel {
    /// With `threads >= 2` a helper thread is started (if the system lets
    /// us; otherwise the main thread does its share).
    pub fn new(model: Arc<Model>, threads: usize) -> Parallel {
        let shared = Arc::new(Shared {
            model,
            job: AtomicU64::new(0),
            claimed: AtomicU64::new(0),
            done: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            sleeping: AtomicBool::new(false),
            system: RwLock::new(System::default()),
            assembly: Mutex::new(AssemblyShare::default()),
            product: Mutex::new(ProductShare::default()),
        });
        RUNNING.fetch_add(1, Ordering::SeqCst);
        let helper = if threads >= 2 && reserve_helper() {
            let for_helper = Arc::clone(&shared);
            let spawned = thread::Builder::new()
                .name("softgrip-solver-helper".into())
                .spawn(move || helper_loop(&for_helper))
                .ok();
            if spawned.is_none() {
                HELPERS.fetch_sub(1, Ordering::SeqCst);
            }
            spawned
        } else {
            None
        };
        Parallel { shared, helper }
    }

    /// The model this split was built for.
    pub fn model(&self) -> &Arc<Model> {
        &self.shared.model
    }

    /// Whether a helper thread shares the work.
    pub fn is_threaded(&self) -> bool {
        self.helper.is_some()
    }

    /// The main thread's system, for assembly.
    pub fn system_mut(&self) -> RwLockWriteGuard<'_, System> {
        self.shared
            .system
            .write()
            .unwrap_or_else(|e| e.into_inner())
    }

    /// The main thread's system, for the solve.
    pub fn system(&self) -> RwLockReadGuard<'_, System> {
        self.shared.system.read().unwrap_or_else(|e| e.into_inner())
    }

    /// The element range the main thread assembles (the helper takes the
    /// ones before it).
    pub fn main_elements(&self) -> std::ops::Range<usize> {
        let n = self.shared.model.tets.len();
        helper_elements(n)..n
    }

    /// The springs whose Rayleigh dashpots the main thread assembles (the helper takes the
    /// ones before them).
    pub fn main_springs(&self) -> std::ops::Range<usize> {
        let n = self.shared.model.springs.len();
        helper_springs(n)..n
    }

    /// Hands the step's positions and velocities to the helper and starts
    /// its share of the force passes.
    pub fn start_assembly(&self, state: &State) {
        {
            let mut share = lock(&self.shared.assembly);
            let s = &mut share.state;
            s.positions.clear();
            s.positions.extend_from_slice(&state.positions);
            s.velocities.clear();
            s.velocities.extend_from_slice(&state.velocities);
            s.maxwell.clear();
            s.maxwell.extend_from_slice(&state.maxwell);
        }
        if self.is_threaded() {
            self.post(ASSEMBLE);
        }
    }

    /// The main thread's share of the split stages: the elements and the springs' dashpots
    /// after the helper's.
    pub fn main_share(&self) -> Share {
        Share {
            elements: self.main_elements(),
            springs: self.main_springs(),
        }
    }

    /// Waits for the helper's share of the force passes and adds it, and its stage timings to
    /// `seconds`.
    pub fn finish_assembly(
        &self,
        force: &mut [DVec3],
        system: &mut System,
        seconds: &mut [f64; Stage::ALL.len()],
    ) {
        if !(self.is_threaded() && self.wait()) {
            assemble(&self.shared);
        }
        let mut share = lock(&self.shared.assembly);
        for (f, g) in force.iter_mut().zip(&share.force) {
            *f += *g;
        }
        system.add(&share.system);
        for (total, helper) in seconds.iter_mut().zip(&mut share.stages.seconds) {
            *total += std::mem::take(helper);
        }
    }

    /// `y = A x` for the `system` read from [`Parallel::system`].
    pub fn product(&self, system: &System, x: &[DVec3], y: &mut [DVec3]) {
        if self.is_threaded() {
            {
                let mut share = lock(&self.shared.product);
                share.x.clear();
                share.x.extend_from_slice(x);
            }
            self.post(PRODUCT);
            system.multiply_first(&self.shared.model.tets, x, y);
            let done = self.wait();
            let mut share = lock(&self.shared.product);
            if !done {
                let ProductShare {
                    x: shared_x,
                    y: second,
                } = &mut *share;
                system.multiply_second(shared_x, second);
            }
            system.multiply_finish(x, y, &share.y);
        } else {
            system.multiply_first(&self.shared.model.tets, x, y);
            let mut share = lock(&self.shared.product);
            system.multiply_second(x, &mut share.y);
            system.multiply_finish(x, y, &share.y);
        }
    }

    fn post(&self, kind: u64) {
        let sequence = (self.shared.job.load(Ordering::Relaxed) >> 2) + 1;
        self.shared
            .job
            .store((sequence << 2) | kind, Ordering::SeqCst);
        if let Some(h) = &self.helper
            && self.shared.sleeping.load(Ordering::SeqCst)
        {
            h.thread().unpark();
        }
    }

    /// Waits for the helper's share of the last job. False if the helper
    /// has not started it (it is claimed back here) or is gone (it
    /// panicked): the caller then does that share itself. Otherwise spins
    /// until the helper has finished, yielding the core if that takes long
    /// (the helper was descheduled mid-job).
    fn wait(&self) -> bool {
        let job = self.shared.job.load(Ordering::Relaxed);
        let previous = self.shared.claimed.load(Ordering::Acquire);
        if previous != job
            && self
                .shared
                .claimed
                .compare_exchange(previous, job, Ordering::AcqRel, Ordering::Acquire)
                .is_ok()
        {
            return false;
        }
        let mut spins = 0u32;
        while self.shared.done.load(Ordering::Acquire) != job {
            spins = spins.wrapping_add(1);
            if spins.is_multiple_of(4096) && self.helper.as_ref().is_none_or(|h| h.is_finished()) {
                return false;
            }
            if spins > 2000 {
                thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
        true
    }
}

impl Drop for Parallel {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        if let Some(h) = self.helper.take() {
            h.thread().unpark();
            // A helper that panicked has nothing left to clean up.
            let _ = h.join();
            HELPERS.fetch_sub(1, Ordering::SeqCst);
        }
        RUNNING.fetch_sub(1, Ordering::SeqCst);
    }
}

fn helper_loop(shared: &Shared) {
    let mut last = 0;
    let mut idle_since = Instant::now();
    let mut spins = 0u32;
    loop {
        if shared.stop.load(Ordering::Acquire) {
            return;
        }
        let job = shared.job.load(Ordering::Acquire);
        if job != last {
            last = job;
            // The main thread may have taken it back already.
            let previous = shared.claimed.load(Ordering::Acquire);
            if previous != job
                && shared
                    .claimed
                    .compare_exchange(previous, job, Ordering::AcqRel, Ordering::Acquire)
                    .is_ok()
            {
                run(shared, job & 3);
                shared.done.store(job, Ordering::Release);
            }
            idle_since = Instant::now();
            spins = 0;
            continue;
        }
        spins = spins.wrapping_add(1);
        if spins > IDLE_SPINS {
            // Let another thread that wants this core have it.
            thread::yield_now();
        }
        if spins.is_multiple_of(256) && idle_since.elapsed() > SPIN_TIME {
            shared.sleeping.store(true, Ordering::SeqCst);
            if shared.job.load(Ordering::SeqCst) == last && !shared.stop.load(Ordering::SeqCst) {
                thread::park_timeout(Duration::from_millis(20));
            }
            shared.sleeping.store(false, Ordering::SeqCst);
            idle_since = Instant::now();
        } else {
            std::hint::spin_loop();
        }
    }
}

fn run(shared: &Shared, kind: u64) {
    match kind {
        ASSEMBLE => assemble(shared),
        PRODUCT => {
            let system = shared.system.read().unwrap_or_else(|e| e.into_inner());
            let mut share = lock(&shared.product);
            let ProductShare { x, y } = &mut *share;
            system.multiply_second(x, y);
        }
        _ => {}
    }
}

/// The helper's share of the force passes: [`HELPER`]'s stages, on the elements before
/// [`Parallel::main_elements`] and the Rayleigh dashpots before [`Parallel::main_springs`].
fn assemble(shared: &Shared) {
    let model = &*shared.model;
    let mut share = lock(&shared.assembly);
    let AssemblyShare {
        state,
        force,
        system,
        stages,
    } = &mut *share;
    system.begin_partial(model, model.dt);
    force.clear();
    force.resize(model.particle_count() + model.fingers.len(), DVec3::ZERO);
    let share = Share {
        elements: 0..helper_elements(model.tets.len()),
        springs: 0..helper_springs(model.springs.len()),
    };
    crate::step::assemble::run(&HELPER, model, state, force, system, &share, stages);
}

/// The helper's share of the springs' Rayleigh dashpots: half.
fn helper_springs(springs: usize) -> usize {
    springs / 2
}

/// The helper's share of the elements: half. It also runs the spring pass,
/// but 2/5 measured no faster on the built-in scene (the main thread then
/// waited less for the helper and did more itself).
fn helper_elements(tets: usize) -> usize {
    tets / 2
}

/// The assembled system seen as an operator for CG.
pub struct SystemOperator<'a> {
    /// The assembled system.
    pub system: &'a System,
    /// The work split whose helper takes half of each product.
    pub parallel: &'a Parallel,
}

impl LinearOperator for SystemOperator<'_> {
    fn apply(&self, x: &[DVec3], y: &mut [DVec3]) {
        self.parallel.product(self.system, x, y);
    }

    fn precondition(&self, r: &[DVec3], z: &mut [DVec3]) {
        self.system.precondition(r, z);
    }

    fn precondition_dot(&self, r: &[DVec3], z: &mut [DVec3]) -> f64 {
        self.system.precondition_dot(r, z)
    }
}

#[cfg(test)]
mod tests {
    use super::{cores, limit_cores};

    #[test]
    fn a_cap_lowers_the_cores_never_raises_them_and_lifts() {
        let machine = cores();
        limit_cores(1);
        assert_eq!(cores(), 1);
        limit_cores(machine + 5);
        assert_eq!(cores(), machine);
        limit_cores(0);
        assert_eq!(cores(), machine);
    }
}
