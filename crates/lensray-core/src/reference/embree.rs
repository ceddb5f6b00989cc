//! Embree's device configuration, the user's to set: `LENSRAY_EMBREE_CONFIG` holds Embree's own
//! configuration string (e.g. `isa=avx2,threads=4`), and every Embree device the CPU reference
//! makes is made from it. Embree ignores keys and values it does not know (`isa=foo` starts a
//! device), so lensray checks the string first and names a bad key or value in one line.
//!
//! Embree picks its kernels at run time: the widest instruction set it was built with that the
//! CPU has, capped by `max_isa` or fixed by `isa`. [`EmbreeSettings::isa`] follows the same rule
//! from the CPU's features; the CLI tests check it against what Embree itself prints
//! (`verbose=1`).

use std::fmt;
use std::sync::OnceLock;

use embree3::{Config, Device, DeviceProperty, FrequencyLevel};

/// The environment variable whose value is passed to Embree's `rtcNewDevice`.
pub const EMBREE_CONFIG_VAR: &str = "LENSRAY_EMBREE_CONFIG";

/// The instruction sets Embree 3 has kernels for, narrowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Isa {
    Sse2,
    Sse42,
    Avx,
    Avx2,
    Avx512,
}

impl Isa {
    pub const ALL: [Isa; 5] = [Isa::Sse2, Isa::Sse42, Isa::Avx, Isa::Avx2, Isa::Avx512];

    /// The name in Embree's configuration string.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Sse2 => "sse2",
            Isa::Sse42 => "sse4.2",
            Isa::Avx => "avx",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    pub fn parse(name: &str) -> Option<Isa> {
        // Embree also reads its older name of the AVX-512 kernels.
        let name = if name == "avx512skx" { "avx512" } else { name };
        Isa::ALL.into_iter().find(|isa| isa.name() == name)
    }

    fn embree(self) -> embree3::Isa {
        match self {
            Isa::Sse2 => embree3::Isa::Sse2,
            Isa::Sse42 => embree3::Isa::Sse4_2,
            Isa::Avx => embree3::Isa::Avx,
            Isa::Avx2 => embree3::Isa::Avx2,
            Isa::Avx512 => embree3::Isa::Avx512,
        }
    }

    /// Whether this CPU has every feature Embree's kernels of this instruction set use (Embree's
    /// `sysinfo.h`: AVX2 also needs FMA, F16C, LZCNT and BMI1/2; its AVX-512 kernels are the
    /// SKX set F, DQ, CD, BW and VL).
    #[cfg(target_arch = "x86_64")]
    pub fn on_this_cpu(self) -> bool {
        use std::arch::is_x86_feature_detected as has;
        let sse42 =
            has!("sse3") && has!("ssse3") && has!("sse4.1") && has!("sse4.2") && has!("popcnt");
        let avx = sse42 && has!("avx");
        let avx2 = avx
            && has!("f16c")
            && has!("avx2")
            && has!("fma")
            && has!("lzcnt")
            && has!("bmi1")
            && has!("bmi2");
        match self {
            Isa::Sse2 => true,
            Isa::Sse42 => sse42,
            Isa::Avx => avx,
            Isa::Avx2 => avx2,
            Isa::Avx512 => {
                avx2 && has!("avx512f")
                    && has!("avx512dq")
                    && has!("avx512cd")
                    && has!("avx512bw")
                    && has!("avx512vl")
            }
        }
    }

    /// Off x86-64 Embree runs its SSE2 kernels through NEON emulation.
    #[cfg(not(target_arch = "x86_64"))]
    pub fn on_this_cpu(self) -> bool {
        self == Isa::Sse2
    }

    /// The instruction sets this CPU runs Embree's kernels of, narrowest first.
    pub fn on_cpu() -> Vec<Isa> {
        Isa::ALL
            .into_iter()
            .filter(|isa| isa.on_this_cpu())
            .collect()
    }
}

impl fmt::Display for Isa {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A checked Embree configuration: what `rtcNewDevice` receives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EmbreeSettings {
    /// The configuration string as the user gave it (empty: Embree's defaults).
    pub text: String,
    pub isa: Option<Isa>,
    pub max_isa: Option<Isa>,
    /// Embree's build threads; 0 is every hardware thread.
    pub threads: u32,
    pub user_threads: u32,
    pub set_affinity: bool,
    pub start_threads: bool,
    pub hugepages: Option<bool>,
    pub verbose: u32,
    pub frequency_level: Option<&'static str>,
}

/// A configuration string lensray refuses, and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{EMBREE_CONFIG_VAR}=\"{text}\": {reason}")]
pub struct EmbreeConfigError {
    pub text: String,
    pub reason: String,
}

const KEYS: &str = "threads, user_threads, set_affinity, start_threads, isa, max_isa, hugepages, \
                    verbose, frequency_level";

impl EmbreeSettings {
    /// Parses Embree's `key=value,key=value` configuration and checks each value, and that this
    /// CPU has the instruction set it asks for.
    pub fn parse(text: &str) -> Result<Self, EmbreeConfigError> {
        Self::parse_for(text, &Isa::on_cpu())
    }

    /// [`EmbreeSettings::parse`] for a CPU that runs `cpu_isas`.
    fn parse_for(text: &str, cpu_isas: &[Isa]) -> Result<Self, EmbreeConfigError> {
        let error = |reason: String| EmbreeConfigError {
            text: text.to_string(),
            reason,
        };
        let mut settings = EmbreeSettings {
            text: text.to_string(),
            ..Default::default()
        };
        for token in text.split(',').map(str::trim).filter(|t| !t.is_empty()) {
            let (key, value) = token
                .split_once('=')
                .map(|(k, v)| (k.trim(), v.trim()))
                .ok_or_else(|| error(format!("`{token}` is not key=value")))?;
            settings
                .set(key, value)
                .map_err(|reason| error(format!("{key}={value}: {reason}")))?;
        }
        let names = || cpu_isas.iter().map(|i| i.name()).collect::<Vec<_>>();
        if let Some(isa) = settings.isa.filter(|isa| !cpu_isas.contains(isa)) {
            return Err(error(format!(
                "this CPU ({}) cannot run Embree's {isa} kernels (it runs {})",
                cpu_name(),
                names().join(", ")
            )));
        }
        Ok(settings)
    }

    fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        let number = || {
            value
                .parse::<u32>()
                .map_err(|_| "not a whole number".to_string())
        };
        let flag = || match value {
            "0" => Ok(false),
            "1" => Ok(true),
            _ => Err("not 0 or 1".to_string()),
        };
        let isa = || {
            Isa::parse(value).ok_or_else(|| {
                let names: Vec<&str> = Isa::ALL.iter().map(|i| i.name()).collect();
                format!(
                    "not one of Embree's instruction sets ({})",
                    names.join(", ")
                )
            })
        };
        match key {
            "threads" => self.threads = number()?,
            "user_threads" => self.user_threads = number()?,
            "set_affinity" => self.set_affinity = flag()?,
            "start_threads" => self.start_threads = flag()?,
            "isa" => self.isa = Some(isa()?),
            "max_isa" => self.max_isa = Some(isa()?),
            "hugepages" => self.hugepages = Some(flag()?),
            "verbose" => self.verbose = number()?.min(3),
            "frequency_level" => {
                self.frequency_level = Some(match value {
                    "simd128" => "simd128",
                    "simd256" => "simd256",
                    "simd512" => "simd512",
                    _ => return Err("not simd128, simd256 or simd512".into()),
                })
            }
            _ => return Err(format!("unknown key (Embree's keys: {KEYS})")),
        }
        Ok(())
    }

    /// The settings of this process: `LENSRAY_EMBREE_CONFIG`, read and checked once.
    pub fn from_env() -> Result<&'static EmbreeSettings, EmbreeConfigError> {
        static SETTINGS: OnceLock<Result<EmbreeSettings, EmbreeConfigError>> = OnceLock::new();
        SETTINGS
            .get_or_init(|| {
                EmbreeSettings::parse(&std::env::var(EMBREE_CONFIG_VAR).unwrap_or_default())
            })
            .as_ref()
            .map_err(Clone::clone)
    }

    /// The instruction set Embree's kernels run: `isa` where set, else the widest this CPU has
    /// up to `max_isa`.
    pub fn isa(&self) -> Isa {
        self.isa.unwrap_or_else(|| {
            let cap = self.max_isa.unwrap_or(Isa::Avx512);
            Isa::on_cpu()
                .into_iter()
                .filter(|&isa| isa <= cap)
                .max()
                .unwrap_or(Isa::Sse2)
        })
    }

    /// An Embree device made with these settings.
    pub fn device(&self) -> Device {
        let device = if self.text.trim().is_empty() {
            Device::new()
        } else {
            Device::with_config(self.config())
        };
        // Embree fails to start only without SSE2, which every x86-64 CPU has.
        device.expect("Embree cannot start on this CPU")
    }

    fn config(&self) -> Config {
        let default = Config::default();
        Config {
            threads: self.threads,
            user_threads: self.user_threads,
            set_affinity: self.set_affinity,
            start_threads: self.start_threads,
            isa: self.isa.map(Isa::embree),
            max_isa: self.max_isa.map_or(default.max_isa, Isa::embree),
            hugepages: self.hugepages.unwrap_or(default.hugepages),
            verbose: self.verbose,
            frequency_level: self.frequency_level.map(|level| match level {
                "simd128" => FrequencyLevel::Simd128,
                "simd256" => FrequencyLevel::Simd256,
                _ => FrequencyLevel::Simd512,
            }),
            ..default
        }
    }
}

/// What `lensray info` says of the CPU path.
#[derive(Clone, Debug)]
pub struct EmbreeReport {
    pub cpu: String,
    /// Embree's version, as its device reports it.
    pub version: String,
    pub isa: Isa,
    /// Every instruction set of Embree's this CPU runs.
    pub cpu_isas: Vec<Isa>,
    /// Embree's build threads (0: every hardware thread).
    pub build_threads: u32,
}

impl EmbreeReport {
    /// Starts an Embree device with the settings and asks it its version.
    pub fn new(settings: &EmbreeSettings) -> Self {
        let device = settings.device();
        let version = device.get_property(DeviceProperty::VERSION).map_or_else(
            |_| "unknown version".into(),
            |v| format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100),
        );
        Self {
            cpu: cpu_name(),
            version,
            isa: settings.isa(),
            cpu_isas: Isa::on_cpu(),
            build_threads: settings.threads,
        }
    }
}

/// The CPU's model name (Linux's /proc/cpuinfo), or its architecture where that is not at hand.
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, name)| name.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_keys_and_refuses_what_embree_would_ignore() {
        let s = EmbreeSettings::parse("isa=sse2, threads=4,verbose=1").unwrap();
        assert_eq!((s.isa, s.threads, s.verbose), (Some(Isa::Sse2), 4, 1));
        assert_eq!(s.isa(), Isa::Sse2);
        let capped = EmbreeSettings::parse("max_isa=sse4.2").unwrap();
        assert_eq!(capped.isa(), Isa::Sse42.min(*Isa::on_cpu().last().unwrap()));
        for (bad, says) in [
            ("isa=foo", "isa=foo: not one of Embree's instruction sets"),
            ("threadz=4", "threadz=4: unknown key"),
            ("threads=abc", "threads=abc: not a whole number"),
            ("avx2", "`avx2` is not key=value"),
            ("hugepages=yes", "hugepages=yes: not 0 or 1"),
        ] {
            let error = EmbreeSettings::parse(bad).unwrap_err().to_string();
            assert!(error.contains(says), "{bad}: {error}");
            assert!(!error.contains('\n'), "{bad}: more than one line: {error}");
        }
    }

    #[test]
    fn isa_the_cpu_lacks_is_refused() {
        let sse_only = [Isa::Sse2, Isa::Sse42];
        let error = EmbreeSettings::parse_for("isa=avx512", &sse_only).unwrap_err();
        assert!(
            error
                .reason
                .contains("cannot run Embree's avx512 kernels (it runs sse2, sse4.2)"),
            "{error}"
        );
        assert!(EmbreeSettings::parse_for("isa=sse4.2", &sse_only).is_ok());
        for isa in Isa::on_cpu() {
            assert_eq!(
                EmbreeSettings::parse(&format!("isa={isa}")).unwrap().isa(),
                isa
            );
        }
    }
}
