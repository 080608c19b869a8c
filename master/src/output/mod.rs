//! What a run leaves behind and prints: the summary, plots, HTML pages, the output folder
//! (claimed, written atomically, never over an input), progress bars and the console.

pub mod console;
pub mod html;
pub mod mode_plots;
pub mod outdir;
pub mod plots;
pub mod progress;
pub mod summary;
pub mod trains;
