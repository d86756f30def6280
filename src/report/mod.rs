//! What catflip tells its users: the commands' reports, tables, plots and files, rendered from
//! what [`crate::measure`] computed (every schedule a [`crate::engines::measured::Measured`]);
//! nothing here measures. A command's entry point ([`run::run`], [`simulate::simulate`],
//! [`import::simulate_import`]) calls `measure` and renders its answer.
//!
//! - [`run`]: `catflip run`, everything for one problem written atomically to `results/<name>/`;
//! - [`simulate`], [`import`], [`compare`], [`optimize`], [`mod@bench`]: the reports of
//!   `catflip simulate` (with or without `--schedule`), `compare`, `optimize` and `bench`;
//! - [`export`]: the one seam between a run's results and its files, an exporter per format
//!   (Markdown, CSV, JSON);
//! - [`check`]: rapier's check of a trajectory against the exact engine, with its verdict;
//! - [`whole`], [`whole_check`], [`whole_files`]: `catflip optimize --whole`, its rapier
//!   verification (`--verify`) and its results folder (`--out`);
//! - [`audit`]: the paper's numbers, published, recomputed and corrected, as Markdown;
//! - [`plot`]: charts and the animation; [`crate::exchange`]: schedules as CSV with URDF/MJCF;
//! - [`robust`]: the robustness check's Markdown, CSV, plots and filmstrips;
//! - [`provenance`]: the header every generated report starts with.

pub mod audit;
pub mod bench;
pub mod check;
pub mod compare;
pub mod export;
pub mod import;
pub mod optimize;
pub mod owned;
pub mod plot;
pub mod provenance;
pub mod results_dir;
pub mod robust;
pub mod run;
pub mod simulate;
pub mod whole;
pub mod whole_check;
pub mod whole_files;
