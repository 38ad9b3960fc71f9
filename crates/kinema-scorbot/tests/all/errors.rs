//! Bad inputs give typed errors with their fields, and I/O failures keep the
//! operating system's error as their source.

use std::io::ErrorKind;
use std::time::Duration;

use kinema_scorbot::acl::Client;
use kinema_scorbot::experiment::Plane;
use kinema_scorbot::sim::Fault;
use kinema_scorbot::Error;

/// The `std::io::Error` at the end of `e`'s source chain, if any.
fn io_source<'a>(e: &'a (dyn std::error::Error + 'static)) -> Option<&'a std::io::Error> {
    let mut cur = e.source();
    let mut found = None;
    while let Some(s) = cur {
        if let Some(io) = s.downcast_ref::<std::io::Error>() {
            found = Some(io);
        }
        cur = s.source();
    }
    found
}

#[test]
fn a_missing_serial_port_keeps_the_os_error() {
    let e = match Client::open_serial("/dev/kinema-no-such-port") {
        Err(e) => e,
        Ok(_) => panic!("opened a port that does not exist"),
    };
    assert!(matches!(&e, Error::Io { during, .. } if during.contains("/dev/kinema-no-such-port")), "{e:?}");
    assert_eq!(io_source(&e).map(|io| io.kind()), Some(ErrorKind::NotFound), "{e:?}");
}

#[test]
fn a_refused_connection_keeps_the_os_error() {
    // A port just freed: nothing listens there.
    let addr = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().to_string();
    let e = match Client::connect_tcp(&addr, Duration::from_secs(2)) {
        Err(e) => e,
        Ok(_) => return, // Something else took the port meanwhile; nothing to check.
    };
    assert!(matches!(&e, Error::Io { during, .. } if during.contains("cannot connect")), "{e:?}");
    assert_eq!(io_source(&e).map(|io| io.kind()), Some(ErrorKind::ConnectionRefused), "{e:?}");
}

#[test]
fn bad_names_and_forms_are_typed() {
    let e = "xw".parse::<Plane>().unwrap_err();
    assert!(matches!(&e, Error::UnknownName { what, name, .. } if what == "plane" && name == "xw"), "{e:?}");
    assert_eq!(e.to_string(), "invalid `plane`: unknown plane `xw`; expected one of: xy, xz, yz");
    let e = "boom@HOME".parse::<Fault>().unwrap_err();
    assert!(matches!(&e, Error::Malformed { what, text, .. } if what == "fault" && text == "boom@HOME"), "{e:?}");
    assert!(e.to_string().contains("unknown fault kind `boom`"), "{e}");
}

#[test]
fn out_of_range_values_are_typed() {
    let side =
        kinema_scorbot::experiment::square(Plane::Xz, kinema::nalgebra::Vector3::new(0.35, 0.0, 0.3), -0.1, 0.0, 0.0);
    let e = side.unwrap_err();
    assert!(matches!(&e, Error::OutOfRange { what, value, .. } if what == "side" && *value == -0.1), "{e:?}");
    assert_eq!(e.to_string(), "invalid `side`: -0.1; expected a finite, positive length [m]");
    let e = kinema_scorbot::experiment::square(
        Plane::Xz,
        kinema::nalgebra::Vector3::new(0.35, f64::NAN, 0.3),
        0.1,
        0.0,
        0.0,
    )
    .unwrap_err();
    assert!(matches!(&e, Error::NotFinite { what, .. } if what == "centre y"), "{e:?}");
}
