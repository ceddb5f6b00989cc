//! `lensray lens NAME|FILE [--json]`: a lens's first-order, real-ray and colour data
//! (`optics::analysis`).

use anyhow::{anyhow, Result};

use lensray_core::optics::analysis::LensData;
use lensray_core::optics::builtin;

#[derive(clap::Args, Debug, Default)]
pub struct LensArgs {
    /// A built-in lens (double-gauss-50, wide-22, ...) or a prescription file.
    #[arg(value_name = "NAME|FILE")]
    pub lens: String,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &LensArgs) -> Result<()> {
    let lens = builtin::resolve(&args.lens).map_err(|e| anyhow!(e))?;
    if let Some(notice) = lens.dispersion_notice() {
        eprintln!("warning: {notice}");
    }
    let data = LensData::of(&lens);
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&data).expect("plain numbers serialise")
        );
    } else {
        print!("{}", data.text());
    }
    Ok(())
}
