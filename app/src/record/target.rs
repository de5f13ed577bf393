//! Where a recording goes: a `.rrd` file (`--rerun FILE`) or a running Rerun viewer
//! (`--rerun-connect ADDR`). A viewer address is checked before anything is sent: the SDK
//! retries an absent viewer forever, so an unreachable address is an error up front.

use anyhow::{bail, Context};
use std::net::{TcpStream, ToSocketAddrs};
use std::path::PathBuf;
use std::time::Duration;

/// A recording's destination.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// Save to this file.
    File(PathBuf),
    /// Stream to the viewer at this gRPC proxy URL (`rerun+http://HOST:PORT/proxy`).
    Connect {
        /// The proxy URL.
        url: String,
        /// `HOST:PORT`.
        address: String,
    },
}

impl Target {
    /// A viewer address: `HOST:PORT`, or a full `rerun+http://HOST:PORT/proxy` URL.
    pub fn connect(addr: &str) -> anyhow::Result<Target> {
        let address = addr
            .trim()
            .strip_prefix("rerun+http://")
            .or_else(|| addr.trim().strip_prefix("rerun+https://"))
            .map(|rest| rest.split('/').next().unwrap_or(""))
            .unwrap_or(addr.trim())
            .to_string();
        let Some((host, port)) = address.rsplit_once(':') else {
            bail!("--rerun-connect `{addr}`: expected HOST:PORT or rerun+http://HOST:PORT/proxy");
        };
        if host.is_empty() || port.parse::<u16>().is_err() {
            bail!("--rerun-connect `{addr}`: `{port}` is not a port number, or the host is empty");
        }
        Ok(Target::Connect {
            url: format!("rerun+http://{address}/proxy"),
            address,
        })
    }

    /// Checks that a viewer listens (within 2 s); a file target needs its folder to exist.
    pub fn check(&self) -> anyhow::Result<()> {
        match self {
            Target::File(path) => {
                if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                    std::fs::create_dir_all(dir)
                        .with_context(|| format!("--rerun: creating {}", dir.display()))?;
                }
                Ok(())
            }
            Target::Connect { address, .. } => {
                let addrs: Vec<_> = address
                    .to_socket_addrs()
                    .with_context(|| format!("--rerun-connect: cannot resolve `{address}`"))?
                    .collect();
                let reachable = addrs
                    .iter()
                    .any(|a| TcpStream::connect_timeout(a, Duration::from_secs(2)).is_ok());
                if !reachable {
                    bail!("--rerun-connect: no Rerun viewer listens at {address} (start one with `rerun`, or save to a file with --rerun FILE.rrd)");
                }
                Ok(())
            }
        }
    }

    /// How the target reads in messages.
    pub fn describe(&self) -> String {
        match self {
            Target::File(p) => p.display().to_string(),
            Target::Connect { url, .. } => url.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_are_parsed_and_bad_ones_named() {
        let t = Target::connect("127.0.0.1:9876").expect("parses");
        assert_eq!(
            t,
            Target::Connect {
                url: "rerun+http://127.0.0.1:9876/proxy".into(),
                address: "127.0.0.1:9876".into()
            }
        );
        let u = Target::connect("rerun+http://localhost:9000/proxy").expect("parses");
        assert_eq!(u.describe(), "rerun+http://localhost:9000/proxy");
        let e = Target::connect("localhost").expect_err("no port");
        assert!(format!("{e}").contains("HOST:PORT"));
        assert!(Target::connect("h:99999").is_err());
    }

    #[test]
    fn an_address_where_nothing_listens_is_refused_at_once() {
        // bind then drop: the port is free and nothing listens there
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let t = Target::connect(&format!("127.0.0.1:{port}")).expect("parses");
        let e = t.check().expect_err("nothing listens");
        assert!(format!("{e}").contains("no Rerun viewer listens"), "{e}");
    }
}
