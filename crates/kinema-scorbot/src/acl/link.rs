//! The byte transports to the controller: TCP and serial.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// A byte transport to the controller with a settable read timeout: a TCP
/// stream, a serial port, or anything else that reads and writes bytes.
pub trait Link: Read + Write + Send {
    /// Sets how long one `read` may block before failing with
    /// `TimedOut`/`WouldBlock`.
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()>;

    /// Reads what has already arrived without waiting: `WouldBlock` when
    /// nothing has. The default waits at most a millisecond.
    fn read_now(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.set_timeout(Duration::from_millis(1))?;
        self.read(buf)
    }
}

impl Link for TcpStream {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.set_read_timeout(Some(timeout.max(Duration::from_millis(1))))
    }

    fn read_now(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.set_nonblocking(true)?;
        let r = self.read(buf);
        self.set_nonblocking(false)?;
        r
    }
}

impl Link for Box<dyn serialport::SerialPort> {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        serialport::SerialPort::set_timeout(self.as_mut(), timeout).map_err(io::Error::from)
    }

    fn read_now(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let waiting = self.bytes_to_read().map_err(io::Error::from)?;
        if waiting == 0 {
            return Err(io::Error::new(io::ErrorKind::WouldBlock, "nothing received"));
        }
        let n = buf.len().min(waiting as usize);
        self.read(&mut buf[..n])
    }
}
