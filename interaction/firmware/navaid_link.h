/* The vibration controller's end of the navaid device link (docs/device-protocol.md).
 *
 * Plain C99, no heap, fixed buffers, only <stdint.h>/<stddef.h>/<string.h>: it builds for the
 * Arduino Mega (eLabrador belt), the Bluno Nano (W-ROMA hand unit) and the STM32 (Smart Cane).
 * The host side is a separate C++ implementation (navaid/interaction/device_protocol.hpp) so
 * that each one tests the other.
 *
 * Use on the microcontroller:
 *   navaid_link_device dev;
 *   navaid_link_device_init(&dev, NAVAID_LINK_DEVICE_BELT, 5, NAVAID_LINK_DEFAULT_TIMEOUT_MS, millis());
 *   loop: navaid_link_device_rx(&dev, bytes, n, millis());     // whatever the UART gave
 *         navaid_link_device_tick(&dev, millis());              // hold expiry, link timeout
 *         for i: set_pwm(i, navaid_link_device_output(&dev, i));
 *         n = navaid_link_device_tx(&dev, out, sizeof out);      // replies to send
 * Time is a free-running uint32 millisecond counter; wrap-around is handled.
 */
#ifndef NAVAID_LINK_H
#define NAVAID_LINK_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NAVAID_LINK_SYNC0 0xA5u
#define NAVAID_LINK_SYNC1 0x5Au
/* sync0 sync1 len type seq_lo seq_hi */
#define NAVAID_LINK_HEADER_SIZE 6u
#define NAVAID_LINK_CRC_SIZE 2u
#define NAVAID_LINK_OVERHEAD (NAVAID_LINK_HEADER_SIZE + NAVAID_LINK_CRC_SIZE)
#define NAVAID_LINK_MAX_ACTUATORS 8u
/* index u8, level i16, on_ms u16, off_ms u16, hold_ms u16 */
#define NAVAID_LINK_ACTUATOR_SIZE 9u
#define NAVAID_LINK_MAX_PAYLOAD (2u + NAVAID_LINK_MAX_ACTUATORS * NAVAID_LINK_ACTUATOR_SIZE)
#define NAVAID_LINK_MAX_FRAME (NAVAID_LINK_OVERHEAD + NAVAID_LINK_MAX_PAYLOAD)
/* A partial frame whose next byte has not come for this long is abandoned and rescanned. */
#define NAVAID_LINK_INTERBYTE_TIMEOUT_MS 50u
#define NAVAID_LINK_DEFAULT_TIMEOUT_MS 1000u
#define NAVAID_LINK_TX_BUFFER 128u

/* Frame types. Host to device below 0x80, device to host from 0x80. */
#define NAVAID_LINK_PATTERN 0x01u
#define NAVAID_LINK_ALL_OFF 0x02u
#define NAVAID_LINK_HEARTBEAT 0x03u
#define NAVAID_LINK_ACK 0x81u
#define NAVAID_LINK_NAK 0x82u
#define NAVAID_LINK_HEARTBEAT_REPLY 0x83u

/* Payload sizes of the fixed-size types. */
#define NAVAID_LINK_ALL_OFF_SIZE 0u
#define NAVAID_LINK_HEARTBEAT_SIZE 1u
#define NAVAID_LINK_ACK_SIZE 3u
#define NAVAID_LINK_NAK_SIZE 4u
#define NAVAID_LINK_HEARTBEAT_REPLY_SIZE 8u

/* HEARTBEAT flags: RESYNC makes the receiver take this frame's sequence as its new base. */
#define NAVAID_LINK_HEARTBEAT_RESYNC 0x01u

/* ACK status */
#define NAVAID_LINK_ACK_APPLIED 0u   /* new frame, carried out */
#define NAVAID_LINK_ACK_DUPLICATE 1u /* same sequence as the last accepted frame: not re-applied */
#define NAVAID_LINK_ACK_STALE 2u     /* older than the last accepted frame: not applied */

/* NAK reasons (the frame had a valid CRC but could not be carried out) */
#define NAVAID_LINK_NAK_BAD_LENGTH 1u   /* detail: the length byte */
#define NAVAID_LINK_NAK_UNKNOWN_TYPE 2u /* detail: the type byte (host types < 0x80 only; device types are ignored) */
#define NAVAID_LINK_NAK_WRONG_DEVICE 3u /* detail: the device kind in the pattern */
#define NAVAID_LINK_NAK_BAD_ACTUATOR 4u /* detail: the actuator index (out of range or repeated) */
#define NAVAID_LINK_NAK_BAD_LEVEL 5u    /* detail: the actuator index */

/* Device kinds, as navaid::interaction::DeviceKind */
#define NAVAID_LINK_DEVICE_BELT 1u
#define NAVAID_LINK_DEVICE_HAND 2u
#define NAVAID_LINK_DEVICE_RUMBLE 3u
#define NAVAID_LINK_DEVICE_WHEEL 4u
#define NAVAID_LINK_MOTOR_LEVEL_MAX 1000

/* Sequence verdict of a delivered frame */
#define NAVAID_LINK_SEQ_NEW 0u
#define NAVAID_LINK_SEQ_DUPLICATE 1u
#define NAVAID_LINK_SEQ_STALE 2u

/* CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, xorout 0; "123456789" -> 0x29B1. */
uint16_t navaid_link_crc16_update(uint16_t crc, const uint8_t* data, size_t n);
uint16_t navaid_link_crc16(const uint8_t* data, size_t n);

/* Writes one frame into out; returns its size, or 0 when len > NAVAID_LINK_MAX_PAYLOAD or the
 * frame does not fit in cap. */
size_t navaid_link_encode(uint8_t type, uint16_t seq, const uint8_t* payload, uint8_t len, uint8_t* out,
                          size_t cap);

typedef struct {
  uint32_t frames_ok;     /* CRC-valid frames of a known type with a valid length (replays included) */
  uint32_t crc_errors;    /* candidate frames whose CRC did not match */
  uint32_t length_errors; /* length byte too large or wrong for the type, or count vs length mismatch */
  uint32_t unknown_type;  /* CRC-valid frames of a type this side does not know */
  uint32_t replayed;      /* frames_ok with a duplicate or stale sequence */
  uint32_t seq_gaps;      /* sequence numbers skipped between consecutive new frames */
  uint32_t truncated;     /* partial frames abandoned after the inter-byte timeout */
  uint32_t resyncs;       /* times the decoder dropped a candidate and searched for the next sync */
  uint32_t dropped_bytes; /* bytes that did not belong to any delivered frame */
} navaid_link_counters;

typedef struct {
  uint8_t type;
  uint8_t len;
  uint16_t seq;
  uint8_t seq_status; /* NAVAID_LINK_SEQ_* */
  const uint8_t* payload;
} navaid_link_frame;

typedef void (*navaid_link_frame_fn)(void* ctx, const navaid_link_frame* frame);

/* Byte-at-a-time decoder of host-to-device frames. */
typedef struct {
  uint8_t raw[NAVAID_LINK_MAX_FRAME];
  uint8_t n;
  uint8_t has_seq;
  uint16_t last_seq;
  navaid_link_counters counters;
} navaid_link_decoder;

void navaid_link_decoder_init(navaid_link_decoder* dec);
/* Feeds n bytes; calls fn for every complete valid frame (payload valid during the call only). */
void navaid_link_decoder_feed(navaid_link_decoder* dec, const uint8_t* data, size_t n, navaid_link_frame_fn fn,
                              void* ctx);
/* Abandons a partial frame (counted as truncated) and rescans its bytes for frames. */
void navaid_link_decoder_flush(navaid_link_decoder* dec, navaid_link_frame_fn fn, void* ctx);
/* The next frame's sequence is accepted as new whatever it is. */
void navaid_link_decoder_forget_sequence(navaid_link_decoder* dec);

typedef struct {
  int16_t level;
  uint16_t on_ms;
  uint16_t off_ms;
  uint16_t hold_ms;
  uint32_t start_ms;
  uint8_t active;
} navaid_link_actuator;

typedef struct {
  uint32_t patterns_applied;
  uint32_t all_off_commands;
  uint32_t heartbeats;
  uint32_t acks_sent; /* queued for sending (a reply that did not fit counts as a tx overflow) */
  uint32_t naks_sent;
  uint32_t hold_expiries; /* actuators switched off because their hold ran out */
  uint32_t link_timeouts; /* times everything was switched off because no valid frame came */
  uint32_t tx_overflows;  /* replies dropped because the transmit buffer was full */
} navaid_link_device_counters;

typedef struct {
  navaid_link_decoder dec;
  uint8_t device_kind;
  uint8_t actuator_count;
  uint8_t link_alive; /* a valid frame came within link_timeout_ms */
  uint32_t link_timeout_ms;
  uint32_t now_ms;
  uint32_t last_valid_ms;
  uint32_t last_byte_ms;
  navaid_link_actuator act[NAVAID_LINK_MAX_ACTUATORS];
  int16_t out[NAVAID_LINK_MAX_ACTUATORS];
  uint16_t tx_seq;
  uint8_t tx[NAVAID_LINK_TX_BUFFER];
  uint16_t tx_head;
  uint16_t tx_len;
  navaid_link_device_counters counters;
} navaid_link_device;

/* actuator_count is clamped to [1, NAVAID_LINK_MAX_ACTUATORS]; link_timeout_ms 0 means the default. */
void navaid_link_device_init(navaid_link_device* dev, uint8_t device_kind, uint8_t actuator_count,
                             uint32_t link_timeout_ms, uint32_t now_ms);
/* Received bytes: decodes, carries out commands and queues the replies. */
void navaid_link_device_rx(navaid_link_device* dev, const uint8_t* data, size_t n, uint32_t now_ms);
/* Hold expiry, pulsing, inter-byte timeout and link timeout; call at least every few ms. */
void navaid_link_device_tick(navaid_link_device* dev, uint32_t now_ms);
/* Moves up to cap queued reply bytes into out; returns how many. */
size_t navaid_link_device_tx(navaid_link_device* dev, uint8_t* out, size_t cap);
/* The drive of actuator index as of the last rx/tick (0 = off). */
int16_t navaid_link_device_output(const navaid_link_device* dev, uint8_t index);
/* Bit i set when actuator i is held (pulsing actuators count in their off phase too). */
uint8_t navaid_link_device_active_mask(const navaid_link_device* dev);

#ifdef __cplusplus
}
#endif

#endif /* NAVAID_LINK_H */
