//! The CPU path feeding the preview: a worker thread adds samples of the current shot, one
//! sample of every pixel at a time, through the `cpu` render path (`paths::CpuPath`, the very
//! code `lensray render --path cpu` runs), and publishes the sums after each;
//! the window uploads the latest to its accumulation. The window itself (G-buffer, display,
//! panel) stays on the GPU, so it keeps answering at once while the CPU traces.

use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;

use anyhow::Result;
use lensray_core::film::{Accumulation, Sums};
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
    pub spp: u32,
}

#[derive(Default)]
struct Shared {
    job: Option<Job>,
    latest: Option<Snapshot>,
    /// Why the worker stopped tracing the current job (a shot the CPU path refuses).
    error: Option<String>,
    quit: bool,
}

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
    let mut accumulation: Option<(u64, Accumulation)> = None;
    loop {
        let Some(job) = next_job(shared, accumulation.as_ref()) else {
            return;
        };
        if accumulation
            .as_ref()
            .is_none_or(|(generation, _)| *generation != job.generation)
        {
            let (width, height) = (job.shot.camera.width, job.shot.camera.height);
            accumulation = Some((job.generation, Accumulation::new(width, height)));
        }
        let (_, sums) = accumulation.as_mut().expect("made above");
        let next = sums.host().map_or(0, Sums::samples);
        let added = path.add_samples(&job.shot, next..next + 1, sums, &mut |_, _| {});
        let mut state = lock.lock().expect("the window does not panic while locked");
        match added.and_then(|()| Ok(sums.host()?.pixels.clone())) {
            Ok(pixels) => {
                state.latest = Some(Snapshot {
                    generation: job.generation,
                    sums: pixels,
                    spp: next + 1,
                });
            }
            Err(e) => {
                // The job stays refused until the window asks for another shot.
                state.error = Some(format!("{e:#}"));
                state.job = None;
            }
        }
    }
}

/// Waits for a job with samples left to trace (`None`: the window closed).
fn next_job(
    shared: &(Mutex<Shared>, Condvar),
    accumulation: Option<&(u64, Accumulation)>,
) -> Option<Job> {
    let (lock, wake) = shared;
    let mut state = lock.lock().expect("the window does not panic while locked");
    loop {
        if state.quit {
            return None;
        }
        if let Some(job) = state.job.clone() {
            let done = accumulation
                .filter(|(generation, _)| *generation == job.generation)
                .map_or(0, |(_, a)| a.host().map_or(0, Sums::samples));
            if done < job.target_spp {
                return Some(job);
            }
        }
        state = wake
            .wait(state)
            .expect("the window does not panic while locked");
    }
}
