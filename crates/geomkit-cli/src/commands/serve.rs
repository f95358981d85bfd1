//! `geomkit serve`: the editor in the browser (crates/geomkit-server).

use crate::cli::ServeArgs;
use anyhow::Result;
use geomkit_server::{Config, ServeOptions};
use std::net::{IpAddr, Ipv4Addr, SocketAddr};

/// Runs the server until the process is stopped.
pub fn run(args: ServeArgs) -> Result<()> {
    let ip = args.bind.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    let mut options = ServeOptions::default();
    options.addr = SocketAddr::new(ip, args.port);
    options.open = args.open;
    options.config = Config::default().with_dir(args.dir);
    geomkit_server::run(options)
}
