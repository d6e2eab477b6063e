//! Clock, EEPROM and serial port twins.

use std::collections::VecDeque;

use embedded_storage::{ReadStorage, Storage};
use touch_arm::config::store::EEPROM_SIZE;
use touch_arm::protocol::rx_loss::{LossCounter, BYTES_PER_FRAME, RX_BUFFER, TX_BUFFER};
use touch_arm::seam::{Clock, RxLoss, SerialPort, StorageError};

/// Millisecond clock set by the runner.
#[derive(Debug, Clone, Default)]
pub struct SimClock {
    /// Milliseconds since power-up; the runner advances it by one frame per step.
    pub ms: u32,
}

impl Clock for SimClock {
    fn now_ms(&self) -> u32 {
        self.ms
    }
}

/// The ATmega2560's 4 KiB EEPROM (erased = 0xFF) with fault injection.
#[derive(Debug, Clone)]
pub struct SimEeprom {
    /// The cells, one byte per address (4 KiB).
    pub mem: Vec<u8>,
    /// Bytes that may still be written before the power fails.
    power_budget: Option<usize>,
    /// Value left in the byte being written when the power fails.
    pub torn_value: u8,
    /// Power is gone: writes are lost until [`SimEeprom::restore_power`].
    dead: bool,
    /// Bytes written (successfully) since creation.
    pub bytes_written: u64,
}

impl Default for SimEeprom {
    fn default() -> Self {
        Self::new()
    }
}

impl SimEeprom {
    /// An erased EEPROM (every cell 0xFF) with the power on.
    pub fn new() -> Self {
        SimEeprom {
            mem: vec![0xFF; EEPROM_SIZE as usize],
            power_budget: None,
            torn_value: 0x00,
            dead: false,
            bytes_written: 0,
        }
    }

    /// Overwrites a byte directly (a corrupted cell).
    pub fn corrupt(&mut self, addr: u16, value: u8) -> Result<(), String> {
        let cell = self.mem.get_mut(addr as usize).ok_or_else(|| format!("eeprom address {addr} out of range"))?;
        *cell = value;
        Ok(())
    }

    /// The power fails after `n` more bytes have been written: byte n + 1 is
    /// left torn and everything after it is lost.
    pub fn power_loss_after(&mut self, n: usize) {
        self.power_budget = Some(n);
    }

    /// Powers the EEPROM again after [`SimEeprom::power_loss_after`]: writes land from now on.
    pub fn restore_power(&mut self) {
        self.power_budget = None;
        self.dead = false;
    }

    /// The power failed (a write ran past the budget of [`SimEeprom::power_loss_after`]) and is not back.
    pub fn is_dead(&self) -> bool {
        self.dead
    }
}

impl ReadStorage for SimEeprom {
    type Error = StorageError;

    fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), StorageError> {
        let a = offset as usize;
        let src = self.mem.get(a..a + buf.len()).ok_or(StorageError::OutOfRange)?;
        buf.copy_from_slice(src);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.mem.len()
    }
}

impl Storage for SimEeprom {
    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), StorageError> {
        let a = offset as usize;
        if a + data.len() > self.mem.len() {
            return Err(StorageError::OutOfRange);
        }
        for (i, &b) in data.iter().enumerate() {
            if self.dead {
                return Ok(());
            }
            match self.power_budget {
                Some(0) => {
                    self.mem[a + i] = self.torn_value;
                    self.dead = true;
                    return Ok(());
                }
                Some(ref mut n) => *n -= 1,
                None => {}
            }
            self.mem[a + i] = b;
            self.bytes_written += 1;
        }
        Ok(())
    }
}

/// USART0's twin: the wire and the chip's bounded receive and transmit
/// buffers (`protocol::rx_loss` sizes), filled and drained at 115200 baud,
/// one frame's worth per [`SimSerial::advance_frame`]. A full receive buffer
/// drops bytes exactly as the chip's interrupt does (through the same
/// `LossCounter`); `write` past the room drops bytes and counts them.
#[derive(Debug, Clone)]
pub struct SimSerial {
    /// Bytes sent to the app, still on the wire.
    pub input: VecDeque<u8>,
    /// Everything the app wrote, in order.
    pub output: Vec<u8>,
    /// Model the buffers (the default). Off: an unbounded port that hands
    /// every sent byte to the app at once and never runs out of room.
    pub bounded: bool,
    ring: VecDeque<u8>,
    loss: LossCounter,
    /// Written bytes not yet sent.
    tx_pending: usize,
    /// Bytes dropped by the receive buffer.
    pub rx_dropped: u64,
    /// Bytes `write` could not queue (a caller that ignored `tx_room`).
    pub tx_overflow: u64,
}

impl Default for SimSerial {
    fn default() -> Self {
        SimSerial {
            input: VecDeque::new(),
            output: Vec::new(),
            bounded: true,
            ring: VecDeque::new(),
            loss: LossCounter::new(),
            tx_pending: 0,
            rx_dropped: 0,
            tx_overflow: 0,
        }
    }
}

impl SimSerial {
    /// Queues `bytes` as if a host had sent them: the app reads them on its next polls.
    pub fn send(&mut self, bytes: &[u8]) {
        self.input.extend(bytes.iter().copied());
    }

    /// One 20 ms frame of the line: up to a frame's worth of bytes arrive
    /// into the receive buffer and as many leave the transmit buffer.
    pub fn advance_frame(&mut self) {
        if !self.bounded {
            return;
        }
        for _ in 0..BYTES_PER_FRAME {
            let Some(b) = self.input.pop_front() else { break };
            let kept = !self.loss.is_open() && self.ring.len() < RX_BUFFER;
            if kept {
                self.ring.push_back(b);
            } else {
                self.rx_dropped += 1;
            }
            self.loss.byte(b, kept);
        }
        self.tx_pending = self.tx_pending.saturating_sub(BYTES_PER_FRAME);
    }

    /// Power cycle: the buffers empty, the wire keeps nothing.
    pub fn reset(&mut self) {
        self.input.clear();
        self.ring.clear();
        self.loss = LossCounter::new();
        self.tx_pending = 0;
    }

    /// Output split into lines (terminators removed; a trailing partial line
    /// is included).
    pub fn lines(&self) -> Vec<String> {
        String::from_utf8_lossy(&self.output)
            .split('\n')
            .map(|l| l.trim_end_matches('\r').to_string())
            .filter(|l| !l.is_empty())
            .collect()
    }
}

impl SerialPort for SimSerial {
    fn read_byte(&mut self) -> Option<u8> {
        if self.bounded {
            self.ring.pop_front()
        } else {
            self.input.pop_front()
        }
    }

    fn take_rx_loss(&mut self) -> Option<RxLoss> {
        if self.ring.is_empty() {
            self.loss.take()
        } else {
            None
        }
    }

    fn tx_room(&self) -> usize {
        if self.bounded {
            TX_BUFFER - self.tx_pending
        } else {
            usize::MAX
        }
    }

    fn write(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(self.tx_room());
        self.output.extend_from_slice(&bytes[..n]);
        self.tx_overflow += (bytes.len() - n) as u64;
        if self.bounded {
            self.tx_pending += n;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_loss_tears_one_byte_and_drops_the_rest() {
        let mut e = SimEeprom::new();
        e.power_loss_after(3);
        e.write(10, &[1, 2, 3, 4, 5]).unwrap();
        assert_eq!(&e.mem[10..16], &[1, 2, 3, 0x00, 0xFF, 0xFF]);
        assert!(e.is_dead());
        e.write(0, &[7]).unwrap();
        assert_eq!(e.mem[0], 0xFF);
        e.restore_power();
        e.write(0, &[7]).unwrap();
        assert_eq!(e.mem[0], 7);
        let mut buf = [0u8; 2];
        assert_eq!(e.read(4095, &mut buf), Err(StorageError::OutOfRange));
        assert_eq!(e.read(4094, &mut buf), Ok(()));
        assert_eq!(e.capacity(), 4096);
        assert!(e.corrupt(4096, 0).is_err());
    }
}
