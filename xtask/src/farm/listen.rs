//! Which addresses listen on a TCP port, read from `/proc/net/tcp` and `/proc/net/tcp6`: the
//! proof that the daemons are reachable from this machine only (127.0.0.1), not from the network.

use std::net::{IpAddr, Ipv4Addr, Ipv6Addr};

/// The local addresses listening on TCP `port` (IPv4 and IPv6).
pub fn listeners(port: u16) -> Vec<IpAddr> {
    ["/proc/net/tcp", "/proc/net/tcp6"]
        .iter()
        .flat_map(|table| parse_table(&std::fs::read_to_string(table).unwrap_or_default(), port))
        .collect()
}

/// Fails unless something listens on each of `ports` and only on loopback addresses.
pub fn require_loopback_only(ports: &[(&str, u16)]) -> Result<(), String> {
    for &(who, port) in ports {
        let addresses = listeners(port);
        if addresses.is_empty() {
            return Err(format!("{who} does not listen on port {port}"));
        }
        if let Some(open) = addresses.iter().find(|a| !a.is_loopback()) {
            return Err(format!("{who} listens on {open}:{port}, not only on 127.0.0.1"));
        }
    }
    Ok(())
}

/// The addresses of the sockets in state LISTEN (0A) on `port` in one `/proc/net/tcp*` table.
fn parse_table(text: &str, port: u16) -> Vec<IpAddr> {
    text.lines()
        .skip(1)
        .filter_map(|line| {
            let mut fields = line.split_whitespace().skip(1);
            let (local, _remote, state) = (fields.next()?, fields.next()?, fields.next()?);
            let (address, local_port) = local.split_once(':')?;
            (state == "0A" && u16::from_str_radix(local_port, 16).ok()? == port).then(|| parse_address(address))?
        })
        .collect()
}

/// An address as the kernel prints it: 32-bit words in hex, each in host (little-endian) order.
fn parse_address(hex: &str) -> Option<IpAddr> {
    let words: Option<Vec<u32>> =
        (0..hex.len() / 8).map(|i| u32::from_str_radix(&hex[8 * i..8 * i + 8], 16).ok()).collect();
    let bytes: Vec<u8> = words?.iter().flat_map(|w| w.to_le_bytes()).collect();
    match bytes.len() {
        4 => Some(IpAddr::V4(Ipv4Addr::new(bytes[0], bytes[1], bytes[2], bytes[3]))),
        16 => Some(IpAddr::V6(Ipv6Addr::from(<[u8; 16]>::try_from(bytes).ok()?))),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listening_sockets_are_read_from_the_kernel_tables() {
        let v4 = "  sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  timeout inode
   0: 00000000:41B1 00000000:0000 0A 00000000:00000000 00:00000000 00000000     0        0 273159 1
   1: 0100007F:41B2 00000000:0000 0A 00000000:00000000 00:00000000 00000000     0        0 273169 1
   2: 0100007F:41B1 0100007F:C356 06 00000000:00000000 03:0000176E 00000000     0        0 0 3";
        assert_eq!(parse_table(v4, 0x41B1), [IpAddr::V4(Ipv4Addr::UNSPECIFIED)], "TIME_WAIT is not listening");
        assert_eq!(parse_table(v4, 0x41B2), [IpAddr::V4(Ipv4Addr::LOCALHOST)]);
        let v6 = "  sl  local_address                         remote_address                        st
   0: 00000000000000000000000001000000:1F90 00000000000000000000000000000000:0000 0A 00000000:00000000";
        assert_eq!(parse_table(v6, 8080), [IpAddr::V6(Ipv6Addr::LOCALHOST)]);
    }

    #[test]
    fn a_port_of_this_process_is_seen_on_loopback() {
        let listener = std::net::TcpListener::bind(("127.0.0.1", 0)).unwrap();
        let port = listener.local_addr().unwrap().port();
        assert_eq!(listeners(port), [IpAddr::V4(Ipv4Addr::LOCALHOST)]);
        require_loopback_only(&[("this test", port)]).unwrap();
        drop(listener);
        // The tests run in parallel: another test's listener may take the freed port at once,
        // and then the port is in use after all; checked only while it is free.
        if listeners(port).is_empty() {
            assert!(require_loopback_only(&[("nobody", port)]).is_err());
        }
    }
}
