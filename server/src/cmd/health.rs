//! `trackd health`: probe a service's `/healthz` (or a bare TCP port) and exit 0 when healthy.
//!
//! Container images built FROM scratch have no `curl`; their `HEALTHCHECK` runs this instead.
//! Plain HTTP/1.1 over `std::net::TcpStream`, no dependency.

use std::{
    io::{Read, Write},
    net::{SocketAddr, TcpStream, ToSocketAddrs},
    time::Duration,
};

use anyhow::{Context, bail};

/// Flags of `trackd health`.
#[derive(clap::Args)]
pub struct Args {
    /// `http://HOST:PORT/PATH` to GET; healthy when it answers 200.
    #[arg(long, required_unless_present = "tcp", conflicts_with = "tcp")]
    url: Option<String>,
    /// `HOST:PORT` to connect to; healthy when it accepts (for the Zenoh router).
    #[arg(long)]
    tcp: Option<String>,
    /// Give up after this long (connect, send and receive each).
    #[arg(long, default_value_t = 2000)]
    timeout_ms: u64,
}

/// Runs `trackd health`: `Ok` (exit 0) when healthy, an error (exit 1) otherwise.
pub fn run(args: Args) -> anyhow::Result<()> {
    let timeout = Duration::from_millis(args.timeout_ms.max(1));
    match (args.url, args.tcp) {
        (Some(url), None) => check_http(&url, timeout),
        (None, Some(addr)) => connect(&addr, timeout).map(drop),
        _ => bail!("give one of --url or --tcp"),
    }
}

/// GETs `url` and succeeds when the status is 200.
fn check_http(url: &str, timeout: Duration) -> anyhow::Result<()> {
    let target = HttpTarget::parse(url)?;
    let mut stream = connect(&target.authority, timeout)?;
    stream.set_read_timeout(Some(timeout))?;
    stream.set_write_timeout(Some(timeout))?;
    let request = format!(
        "GET {} HTTP/1.1\r\nHost: {}\r\nUser-Agent: trackd-health\r\nConnection: close\r\n\r\n",
        target.path, target.authority
    );
    stream
        .write_all(request.as_bytes())
        .with_context(|| format!("sending to {}", target.authority))?;
    let status =
        read_status_line(&mut stream).with_context(|| format!("reading the answer of {url}"))?;
    match status_code(&status) {
        Some(200) => Ok(()),
        Some(code) => bail!("{url} answered {code}"),
        None => bail!("{url} answered something that is not HTTP: {status:?}"),
    }
}

/// Opens a TCP connection to `authority` (`HOST:PORT`), trying each resolved address.
fn connect(authority: &str, timeout: Duration) -> anyhow::Result<TcpStream> {
    let addrs: Vec<SocketAddr> = authority
        .to_socket_addrs()
        .with_context(|| format!("resolving {authority}"))?
        .collect();
    let mut last_error = None;
    for addr in &addrs {
        match TcpStream::connect_timeout(addr, timeout) {
            Ok(stream) => return Ok(stream),
            Err(e) => last_error = Some(e),
        }
    }
    match last_error {
        Some(e) => Err(e).with_context(|| format!("connecting to {authority}")),
        None => bail!("{authority} resolves to no address"),
    }
}

/// Reads up to the end of the first line (at most 1 KiB).
fn read_status_line(stream: &mut impl Read) -> anyhow::Result<String> {
    let mut line = Vec::new();
    let mut byte = [0u8; 1];
    while line.len() < 1024 {
        if stream.read(&mut byte)? == 0 {
            break;
        }
        if byte[0] == b'\n' {
            break;
        }
        line.push(byte[0]);
    }
    if line.is_empty() {
        bail!("the connection closed without an answer");
    }
    Ok(String::from_utf8_lossy(&line).trim_end().to_owned())
}

/// The status code of `HTTP/1.x CODE REASON`.
fn status_code(status_line: &str) -> Option<u16> {
    let mut parts = status_line.split_whitespace();
    let version = parts.next()?;
    if !version.starts_with("HTTP/") {
        return None;
    }
    parts.next()?.parse().ok()
}

/// The parts of an `http://` URL that a GET needs.
#[derive(Debug, PartialEq)]
struct HttpTarget {
    /// `HOST:PORT` (port 80 added when absent).
    authority: String,
    /// `/PATH?QUERY` (`/` when absent).
    path: String,
}

impl HttpTarget {
    fn parse(url: &str) -> anyhow::Result<Self> {
        let Some(rest) = url.strip_prefix("http://") else {
            bail!("{url:?}: only http:// URLs are supported");
        };
        let (authority, path) = match rest.find('/') {
            Some(i) => (&rest[..i], &rest[i..]),
            None => (rest, "/"),
        };
        if authority.is_empty() {
            bail!("{url:?}: no host");
        }
        let has_port = match authority.rfind(']') {
            Some(bracket) => authority[bracket..].contains(':'),
            None => authority.contains(':'),
        };
        let authority = if has_port {
            authority.to_owned()
        } else {
            format!("{authority}:80")
        };
        Ok(Self {
            authority,
            path: path.to_owned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use std::{net::TcpListener, thread};

    use super::*;

    /// Serves one connection with `answer` and returns the request it received.
    fn serve_once(answer: &'static [u8]) -> (String, thread::JoinHandle<String>) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let handle = thread::spawn(move || {
            let (mut conn, _) = listener.accept().unwrap();
            let mut request = Vec::new();
            let mut buf = [0u8; 512];
            while !request.ends_with(b"\r\n\r\n") {
                let n = conn.read(&mut buf).unwrap();
                if n == 0 {
                    break;
                }
                request.extend_from_slice(&buf[..n]);
            }
            conn.write_all(answer).unwrap();
            String::from_utf8(request).unwrap()
        });
        (format!("http://{addr}/healthz"), handle)
    }

    #[test]
    fn healthy_on_200_and_sends_a_proper_get() {
        let (url, server) = serve_once(b"HTTP/1.1 200 OK\r\ncontent-length: 2\r\n\r\nok");
        check_http(&url, Duration::from_secs(2)).unwrap();
        let request = server.join().unwrap();
        assert!(
            request.starts_with("GET /healthz HTTP/1.1\r\n"),
            "{request}"
        );
        assert!(request.contains("\r\nHost: 127.0.0.1:"), "{request}");
    }

    #[test]
    fn unhealthy_on_other_status() {
        let (url, server) = serve_once(b"HTTP/1.1 503 Service Unavailable\r\n\r\n");
        let err = check_http(&url, Duration::from_secs(2)).unwrap_err();
        assert!(err.to_string().contains("503"), "{err}");
        server.join().unwrap();
    }

    #[test]
    fn unhealthy_on_garbage_or_silence() {
        let (url, server) = serve_once(b"SSH-2.0-OpenSSH\r\n");
        assert!(check_http(&url, Duration::from_secs(2)).is_err());
        server.join().unwrap();
        let (url, server) = serve_once(b"");
        assert!(check_http(&url, Duration::from_secs(2)).is_err());
        server.join().unwrap();
    }

    #[test]
    fn unhealthy_when_nothing_listens() {
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let url = format!("http://127.0.0.1:{port}/healthz");
        assert!(check_http(&url, Duration::from_millis(500)).is_err());
        assert!(connect(&format!("127.0.0.1:{port}"), Duration::from_millis(500)).is_err());
    }

    #[test]
    fn tcp_probe_accepts_a_listening_port() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        assert!(connect(&addr, Duration::from_millis(500)).is_ok());
    }

    #[test]
    fn parses_urls() {
        let t = HttpTarget::parse("http://127.0.0.1:8080/healthz").unwrap();
        assert_eq!(t.authority, "127.0.0.1:8080");
        assert_eq!(t.path, "/healthz");
        let t = HttpTarget::parse("http://vehicle-1").unwrap();
        assert_eq!(t.authority, "vehicle-1:80");
        assert_eq!(t.path, "/");
        let t = HttpTarget::parse("http://[::1]/x?y=1").unwrap();
        assert_eq!(t.authority, "[::1]:80");
        assert_eq!(t.path, "/x?y=1");
        assert!(HttpTarget::parse("https://a/b").is_err());
        assert!(HttpTarget::parse("http:///b").is_err());
    }

    #[test]
    fn reads_status_codes() {
        assert_eq!(status_code("HTTP/1.1 200 OK"), Some(200));
        assert_eq!(status_code("HTTP/1.0 404"), Some(404));
        assert_eq!(status_code("200 OK"), None);
        assert_eq!(status_code("HTTP/1.1"), None);
    }
}
