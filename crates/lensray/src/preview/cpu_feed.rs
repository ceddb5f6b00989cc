//! The CPU path feeding the preview: a worker thread adds samples of the current shot, one
//! sample of every pixel at a time, through the `cpu` render path (`paths::CpuPath`, the very
//! code `lensray render --path cpu` runs), and publishes the sums after each;
//! the window uploads the latest to its accumulation. The window itself (G-buffer, display,
//! panel) stays on the GPU, so it keeps answering at once while the CPU traces. With a noise
//! threshold it adds a round of adaptive sampling at a time instead (`film::adaptive`, as
//! `render --path cpu`), publishing after each.

use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;

use anyhow::Result;
use lensray_core::film::adaptive::{min_samples, AdaptiveState, STEP};
use lensray_core::film::{Accumulation, Sums};
use lensray_core::scene::motion::ObjectMotion;
use lensray_core::scene::Scene;
use lensray_core::settings::Shot;

use crate::paths::{CpuPath, RenderPath};

/// What the worker should trace.
#[derive(Clone)]
struct Job {
    generation: u64,
    shot: Shot,
    target_spp: u32,
}

/// Sums of the shot of one generation.
pub struct Snapshot {
    pub generation: u64,
    pub sums: Vec<[f32; 4]>,
    /// Samples every pixel has (adaptively: the pixels still sampling).
    pub spp: u32,
    /// No pixel takes more samples.
    pub converged: bool,
    /// Adaptively: the pixels that take samples in the next round (`None`: uniform).
    pub adaptive_active: Option<usize>,
}

/// The accumulation of one generation and target, with adaptive sampling's rounds.
struct Traced {
    generation: u64,
    target_spp: u32,
    accumulation: Accumulation,
    /// With a noise threshold: the rounds' state, and where the next round ends (`None`:
    /// every pixel converged or reached the cap).
    rounds: Option<(AdaptiveState, Option<u32>)>,
}

impl Traced {
    fn new(job: &Job) -> Self {
        let (width, height) = (job.shot.camera.width, job.shot.camera.height);
        let rounds = job
            .shot
            .render
            .noise_threshold
            .filter(|_| !job.shot.render.shading.is_aov())
            .map(|t| {
                let first = min_samples(t, job.target_spp);
                (AdaptiveState::new(width, height), Some(first))
            });
        Self {
            generation: job.generation,
            target_spp: job.target_spp,
            accumulation: Accumulation::new(width, height),
            rounds,
        }
    }

    /// Whether `job` is this accumulation's: its shot, and with rounds its target too (a new
    /// cap starts the rounds again; uniform samples continue).
    fn of(&self, job: &Job) -> bool {
        self.generation == job.generation
            && (self.rounds.is_none() || self.target_spp == job.target_spp)
    }

    /// No sample is left to add for `job`.
    fn finished(&self, job: &Job) -> bool {
        match &self.rounds {
            Some((_, next)) => next.is_none(),
            None => self.accumulation.host().map_or(0, Sums::samples) >= job.target_spp,
        }
    }

    /// Adds the next sample of every pixel, or the next round, and says what the sums hold.
    fn add(&mut self, path: &mut CpuPath, job: &Job) -> Result<Snapshot> {
        let accumulation = &mut self.accumulation;
        let (spp, converged, adaptive_active) = match &mut self.rounds {
            Some((state, next)) => {
                let end = next.unwrap_or(job.target_spp);
                let threshold = job.shot.render.noise_threshold.unwrap_or(f32::INFINITY);
                let (active, class_a) = (state.active.clone(), &mut state.class_a);
                path.add_round(&job.shot, end, &active, accumulation, class_a)?;
                let active = state.mark_active(accumulation.host()?, threshold, job.target_spp);
                let more = active > 0 && end < job.target_spp;
                *next = more.then(|| (end + STEP).min(job.target_spp));
                (end, !more, Some(if more { active } else { 0 }))
            }
            None => {
                let next = accumulation.host().map_or(0, Sums::samples);
                path.add_samples(&job.shot, next..next + 1, accumulation, &mut |_, _| {})?;
                (next + 1, next + 1 >= job.target_spp, None)
            }
        };
        Ok(Snapshot {
            generation: job.generation,
            sums: accumulation.host()?.pixels.clone(),
            spp,
            converged,
            adaptive_active,
        })
    }
}

#[derive(Default)]
struct Shared {
    job: Option<Job>,
    /// A scene to trace from the next job on (an animated file's next pose).
    scene: Option<SceneToLoad>,
    latest: Option<Snapshot>,
    /// Why the worker stopped tracing the current job (a shot the CPU path refuses).
    error: Option<String>,
    quit: bool,
}

/// A scene for the worker to load, and its meshes' motion over the frame's shutter.
type SceneToLoad = (Scene, Option<ObjectMotion>);

pub struct CpuFeed {
    shared: Arc<(Mutex<Shared>, Condvar)>,
    worker: Option<JoinHandle<()>>,
    generation: u64,
    current: Option<(Shot, u32)>,
}

impl CpuFeed {
    /// Opens the CPU path on `scene` (its BVH built here) and starts the worker.
    pub fn new(scene: &Scene) -> Result<Self> {
        let mut path = CpuPath::new();
        path.load_scene(scene)?;
        let shared = Arc::new((Mutex::new(Shared::default()), Condvar::new()));
        let worker_shared = shared.clone();
        let worker = std::thread::Builder::new()
            .name("lensray cpu path".into())
            .spawn(move || work(&mut path, &worker_shared))
            .expect("a thread can be started");
        Ok(Self {
            shared,
            worker: Some(worker),
            generation: 0,
            current: None,
        })
    }

    /// Asks for `target_spp` samples of `shot`; a new shot restarts from 0 samples, a new
    /// target continues.
    pub fn request(&mut self, shot: &Shot, target_spp: u32) {
        if self
            .current
            .as_ref()
            .is_some_and(|(s, t)| s == shot && *t == target_spp)
        {
            return;
        }
        let new_shot = self.current.as_ref().is_none_or(|(s, _)| s != shot);
        if new_shot {
            self.generation += 1;
        }
        self.current = Some((shot.clone(), target_spp));
        let (lock, wake) = &*self.shared;
        let mut shared = lock.lock().expect("the worker does not panic");
        shared.job = Some(Job {
            generation: self.generation,
            shot: shot.clone(),
            target_spp,
        });
        wake.notify_all();
    }

    /// Traces `scene` from the next request on (an animated file's pose of another frame),
    /// the meshes `motion` names moving over the frame's shutter: the next request starts
    /// from 0 samples, even of the same shot.
    pub fn load_scene(&mut self, scene: &Scene, motion: Option<&ObjectMotion>) {
        self.current = None;
        let (lock, wake) = &*self.shared;
        let mut shared = lock.lock().expect("the worker does not panic");
        shared.scene = Some((scene.clone(), motion.cloned()));
        shared.job = None;
        shared.latest = None;
        wake.notify_all();
    }

    /// The newest sums of the current shot, if any arrived since the last call; an error when
    /// the CPU path refused the shot.
    pub fn take_latest(&mut self) -> Result<Option<Snapshot>> {
        let (lock, _) = &*self.shared;
        let mut shared = lock.lock().expect("the worker does not panic");
        if let Some(error) = shared.error.take() {
            anyhow::bail!("the CPU path: {error}");
        }
        Ok(shared
            .latest
            .take()
            .filter(|s| s.generation == self.generation))
    }
}

impl Drop for CpuFeed {
    fn drop(&mut self) {
        {
            let (lock, wake) = &*self.shared;
            if let Ok(mut shared) = lock.lock() {
                shared.quit = true;
            }
            wake.notify_all();
        }
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

/// The worker: traces one sample of every pixel at a time for the newest job, publishing the
/// sums after each; sleeps when the target is reached.
fn work(path: &mut CpuPath, shared: &(Mutex<Shared>, Condvar)) {
    let (lock, _) = shared;
    let mut traced: Option<Traced> = None;
    loop {
        let Some((job, scene)) = next_job(shared, traced.as_ref()) else {
            return;
        };
        if let Some((scene, motion)) = scene {
            traced = None;
            let loaded = match &motion {
                Some(motion) => path.load_moving_scene(&scene, motion),
                None => path.load_scene(&scene),
            };
            if let Err(e) = loaded {
                let mut state = lock.lock().expect("the window does not panic while locked");
                state.error = Some(format!("{e:#}"));
                state.job = None;
                continue;
            }
        }
        if traced.as_ref().is_none_or(|t| !t.of(&job)) {
            traced = Some(Traced::new(&job));
        }
        let added = traced.as_mut().expect("made above").add(path, &job);
        let mut state = lock.lock().expect("the window does not panic while locked");
        match added {
            Ok(snapshot) => {
                state.latest = Some(snapshot);
            }
            Err(e) => {
                // The job stays refused until the window asks for another shot.
                state.error = Some(format!("{e:#}"));
                state.job = None;
            }
        }
    }
}

/// Waits for a job with samples left to trace, with the scene to load first if a new one
/// came (`None`: the window closed).
fn next_job(
    shared: &(Mutex<Shared>, Condvar),
    traced: Option<&Traced>,
) -> Option<(Job, Option<SceneToLoad>)> {
    let (lock, wake) = shared;
    let mut state = lock.lock().expect("the window does not panic while locked");
    loop {
        if state.quit {
            return None;
        }
        if let Some(job) = state.job.clone() {
            if state.scene.is_some() {
                return Some((job, state.scene.take()));
            }
            let finished = traced.is_some_and(|t| t.of(&job) && t.finished(&job));
            if !finished {
                return Some((job, None));
            }
        }
        state = wake
            .wait(state)
            .expect("the window does not panic while locked");
    }
}
