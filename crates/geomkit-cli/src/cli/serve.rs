//! Arguments of `geomkit serve`.

use clap::Args;
use std::net::IpAddr;
use std::path::PathBuf;

/// Arguments of `serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// Port to listen on (0: a free port, printed on the first line).
    #[arg(long, short, default_value_t = 8765)]
    pub port: u16,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// Folder whose model files (.json) the page may open and save; without it the page
    /// has no file access (exports are downloads).
    #[arg(long, value_name = "FOLDER")]
    pub dir: Option<PathBuf>,
    /// Address to bind [default: 127.0.0.1]. Browsers must still name a local host (the
    /// server refuses other Host and Origin headers), but another address exposes the API
    /// to every program that can reach it: keep the default unless you mean that.
    #[arg(long, value_name = "IP")]
    pub bind: Option<IpAddr>,
}
