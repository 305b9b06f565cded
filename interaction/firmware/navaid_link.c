/* The vibration controller's end of the navaid device link; see navaid_link.h and
 * docs/device-protocol.md. */
#include "navaid_link.h"

#include <string.h>

static uint16_t get_u16(const uint8_t* p) { return (uint16_t)((unsigned)p[0] | ((unsigned)p[1] << 8u)); }

static void put_u16(uint8_t* p, uint16_t v) {
  p[0] = (uint8_t)(v & 0xFFu);
  p[1] = (uint8_t)(v >> 8u);
}

/* Bitwise so that it needs no 512-byte table in an AVR's RAM; a frame is at most 82 bytes. */
uint16_t navaid_link_crc16_update(uint16_t crc, const uint8_t* data, size_t n) {
  size_t i;
  for (i = 0; i < n; ++i) {
    unsigned bit;
    crc = (uint16_t)(crc ^ (uint16_t)((unsigned)data[i] << 8u));
    for (bit = 0; bit < 8u; ++bit) {
      crc = (crc & 0x8000u) ? (uint16_t)((unsigned)(crc << 1u) ^ 0x1021u) : (uint16_t)(crc << 1u);
    }
  }
  return crc;
}

uint16_t navaid_link_crc16(const uint8_t* data, size_t n) { return navaid_link_crc16_update(0xFFFFu, data, n); }

size_t navaid_link_encode(uint8_t type, uint16_t seq, const uint8_t* payload, uint8_t len, uint8_t* out,
                          size_t cap) {
  const size_t total = NAVAID_LINK_OVERHEAD + (size_t)len;
  uint16_t crc;
  if (len > NAVAID_LINK_MAX_PAYLOAD || cap < total || out == NULL || (len > 0u && payload == NULL)) return 0;
  out[0] = NAVAID_LINK_SYNC0;
  out[1] = NAVAID_LINK_SYNC1;
  out[2] = len;
  out[3] = type;
  put_u16(out + 4, seq);
  if (len > 0u) memcpy(out + NAVAID_LINK_HEADER_SIZE, payload, len);
  crc = navaid_link_crc16(out + 2, (size_t)4u + len);
  put_u16(out + NAVAID_LINK_HEADER_SIZE + len, crc);
  return total;
}

/* ---------------------------------------------------------------------------------------------
 * Decoder */

/* 1: known host-to-device type with a valid length, 0: known type, wrong length, -1: unknown. */
static int length_fits_type(uint8_t type, uint8_t len) {
  switch (type) {
    case NAVAID_LINK_PATTERN:
      return (len >= 2u && (len - 2u) % NAVAID_LINK_ACTUATOR_SIZE == 0u) ? 1 : 0;
    case NAVAID_LINK_ALL_OFF:
      return len == NAVAID_LINK_ALL_OFF_SIZE ? 1 : 0;
    case NAVAID_LINK_HEARTBEAT:
      return len == NAVAID_LINK_HEARTBEAT_SIZE ? 1 : 0;
    default:
      return -1;
  }
}

void navaid_link_decoder_init(navaid_link_decoder* dec) { memset(dec, 0, sizeof *dec); }

void navaid_link_decoder_forget_sequence(navaid_link_decoder* dec) { dec->has_seq = 0; }

/* Drops the first byte and everything up to the next possible sync byte. */
static void drop_to_next_sync(navaid_link_decoder* dec) {
  size_t k = 1;
  while (k < dec->n && dec->raw[k] != NAVAID_LINK_SYNC0) ++k;
  dec->counters.dropped_bytes += (uint32_t)k;
  memmove(dec->raw, dec->raw + k, dec->n - k);
  dec->n = (uint8_t)(dec->n - k);
}

static void abandon(navaid_link_decoder* dec, uint32_t* counter) {
  if (counter != NULL) ++*counter;
  ++dec->counters.resyncs;
  drop_to_next_sync(dec);
}

static uint8_t classify_sequence(navaid_link_decoder* dec, const navaid_link_frame* f) {
  const int anchor = f->type == NAVAID_LINK_HEARTBEAT && (f->payload[0] & NAVAID_LINK_HEARTBEAT_RESYNC) != 0u;
  uint16_t diff;
  if (!dec->has_seq || anchor) {
    dec->has_seq = 1;
    dec->last_seq = f->seq;
    return NAVAID_LINK_SEQ_NEW;
  }
  diff = (uint16_t)(f->seq - dec->last_seq);
  if (diff == 0u) return NAVAID_LINK_SEQ_DUPLICATE;
  if (diff >= 0x8000u) return NAVAID_LINK_SEQ_STALE;
  dec->counters.seq_gaps += (uint32_t)(diff - 1u);
  dec->last_seq = f->seq;
  return NAVAID_LINK_SEQ_NEW;
}

static void process(navaid_link_decoder* dec, navaid_link_frame_fn fn, void* ctx);

void navaid_link_decoder_feed(navaid_link_decoder* dec, const uint8_t* data, size_t n, navaid_link_frame_fn fn,
                              void* ctx) {
  size_t i;
  for (i = 0; i < n; ++i) {
    /* process() keeps n below the largest frame, so there is always room for one more byte. */
    dec->raw[dec->n++] = data[i];
    process(dec, fn, ctx);
  }
}

void navaid_link_decoder_flush(navaid_link_decoder* dec, navaid_link_frame_fn fn, void* ctx) {
  if (dec->n == 0u) return;
  ++dec->counters.truncated;
  while (dec->n > 0u) {
    if (dec->n >= 2u && dec->raw[0] == NAVAID_LINK_SYNC0 && dec->raw[1] == NAVAID_LINK_SYNC1) {
      abandon(dec, NULL);
    } else {
      drop_to_next_sync(dec);
    }
    process(dec, fn, ctx);
  }
}

static void process(navaid_link_decoder* dec, navaid_link_frame_fn fn, void* ctx) {
  for (;;) {
    uint8_t len;
    int fits;
    size_t total;
    navaid_link_frame f;
    if (dec->n == 0u) return;
    if (dec->raw[0] != NAVAID_LINK_SYNC0) {
      drop_to_next_sync(dec);
      continue;
    }
    if (dec->n < 2u) return;
    if (dec->raw[1] != NAVAID_LINK_SYNC1) {
      drop_to_next_sync(dec);
      continue;
    }
    if (dec->n < 3u) return;
    len = dec->raw[2];
    if (len > NAVAID_LINK_MAX_PAYLOAD) {
      abandon(dec, &dec->counters.length_errors);
      continue;
    }
    if (dec->n < 4u) return;
    fits = length_fits_type(dec->raw[3], len);
    if (fits == 0) {
      abandon(dec, &dec->counters.length_errors);
      continue;
    }
    total = NAVAID_LINK_OVERHEAD + (size_t)len;
    if (dec->n < total) return;
    if (navaid_link_crc16(dec->raw + 2, (size_t)4u + len) != get_u16(dec->raw + NAVAID_LINK_HEADER_SIZE + len)) {
      abandon(dec, &dec->counters.crc_errors);
      continue;
    }
    f.type = dec->raw[3];
    f.len = len;
    f.seq = get_u16(dec->raw + 4);
    f.payload = dec->raw + NAVAID_LINK_HEADER_SIZE;
    f.seq_status = NAVAID_LINK_SEQ_NEW;
    if (fits < 0) {
      ++dec->counters.unknown_type;
    } else if (f.type == NAVAID_LINK_PATTERN && (size_t)f.payload[1] * NAVAID_LINK_ACTUATOR_SIZE + 2u != len) {
      ++dec->counters.length_errors;
    } else {
      ++dec->counters.frames_ok;
      f.seq_status = classify_sequence(dec, &f);
      if (f.seq_status != NAVAID_LINK_SEQ_NEW) ++dec->counters.replayed;
    }
    if (fn != NULL) fn(ctx, &f);
    memmove(dec->raw, dec->raw + total, dec->n - total);
    dec->n = (uint8_t)(dec->n - total);
  }
}

/* ---------------------------------------------------------------------------------------------
 * Device */

/* 1 when the reply was queued, 0 when it was dropped (counted as a tx overflow). */
static int queue_reply(navaid_link_device* dev, uint8_t type, const uint8_t* payload, uint8_t len) {
  uint8_t frame[NAVAID_LINK_OVERHEAD + NAVAID_LINK_HEARTBEAT_REPLY_SIZE];
  const size_t size = navaid_link_encode(type, dev->tx_seq, payload, len, frame, sizeof frame);
  size_t i;
  if (size == 0u || dev->tx_len + size > NAVAID_LINK_TX_BUFFER) {
    ++dev->counters.tx_overflows;
    return 0;
  }
  dev->tx_seq = (uint16_t)(dev->tx_seq + 1u);
  for (i = 0; i < size; ++i) {
    dev->tx[(dev->tx_head + dev->tx_len) % NAVAID_LINK_TX_BUFFER] = frame[i];
    ++dev->tx_len;
  }
  return 1;
}

static void send_ack(navaid_link_device* dev, uint16_t seq, uint8_t status) {
  uint8_t p[NAVAID_LINK_ACK_SIZE];
  put_u16(p, seq);
  p[2] = status;
  /* Counted only when it really goes out: a dropped ACK is a tx overflow. */
  if (queue_reply(dev, NAVAID_LINK_ACK, p, sizeof p)) ++dev->counters.acks_sent;
}

static void send_nak(navaid_link_device* dev, uint16_t seq, uint8_t reason, uint8_t detail) {
  uint8_t p[NAVAID_LINK_NAK_SIZE];
  put_u16(p, seq);
  p[2] = reason;
  p[3] = detail;
  if (queue_reply(dev, NAVAID_LINK_NAK, p, sizeof p)) ++dev->counters.naks_sent;
}

static void all_off(navaid_link_device* dev) {
  uint8_t i;
  for (i = 0; i < NAVAID_LINK_MAX_ACTUATORS; ++i) {
    dev->act[i].active = 0;
    dev->out[i] = 0;
  }
}

static void update_outputs(navaid_link_device* dev) {
  uint8_t i;
  for (i = 0; i < dev->actuator_count; ++i) {
    navaid_link_actuator* a = &dev->act[i];
    uint32_t elapsed;
    if (!a->active) {
      dev->out[i] = 0;
      continue;
    }
    elapsed = dev->now_ms - a->start_ms;
    if (elapsed >= a->hold_ms) {
      a->active = 0;
      dev->out[i] = 0;
      ++dev->counters.hold_expiries;
    } else if (a->on_ms == 0u || a->off_ms == 0u) {
      dev->out[i] = a->level;
    } else {
      const uint32_t period = (uint32_t)a->on_ms + a->off_ms;
      dev->out[i] = (elapsed % period) < a->on_ms ? a->level : (int16_t)0;
    }
  }
}

/* Checks a PATTERN; 0 when it can be applied, otherwise the NAK reason (detail in *detail). */
static uint8_t check_pattern(const navaid_link_device* dev, const navaid_link_frame* f, uint8_t* detail) {
  const uint8_t count = f->payload[1];
  uint16_t seen = 0;
  uint8_t k;
  if (f->payload[0] != dev->device_kind) {
    *detail = f->payload[0];
    return NAVAID_LINK_NAK_WRONG_DEVICE;
  }
  for (k = 0; k < count; ++k) {
    const uint8_t* c = f->payload + 2u + (size_t)k * NAVAID_LINK_ACTUATOR_SIZE;
    const int16_t level = (int16_t)get_u16(c + 1);
    *detail = c[0];
    if (c[0] >= dev->actuator_count || (seen & (1u << c[0])) != 0u) return NAVAID_LINK_NAK_BAD_ACTUATOR;
    seen = (uint16_t)(seen | (1u << c[0]));
    if (dev->device_kind != NAVAID_LINK_DEVICE_WHEEL && (level < 0 || level > NAVAID_LINK_MOTOR_LEVEL_MAX)) {
      return NAVAID_LINK_NAK_BAD_LEVEL;
    }
  }
  *detail = 0;
  return 0;
}

static void apply_pattern(navaid_link_device* dev, const navaid_link_frame* f) {
  const uint8_t count = f->payload[1];
  uint8_t k;
  all_off(dev);
  for (k = 0; k < count; ++k) {
    const uint8_t* c = f->payload + 2u + (size_t)k * NAVAID_LINK_ACTUATOR_SIZE;
    navaid_link_actuator* a = &dev->act[c[0]];
    a->level = (int16_t)get_u16(c + 1);
    a->on_ms = get_u16(c + 3);
    a->off_ms = get_u16(c + 5);
    a->hold_ms = get_u16(c + 7);
    a->start_ms = dev->now_ms;
    a->active = (uint8_t)(a->level != 0 && a->hold_ms > 0u);
  }
  ++dev->counters.patterns_applied;
  update_outputs(dev);
}

static uint8_t ack_status(uint8_t seq_status) {
  return seq_status == NAVAID_LINK_SEQ_DUPLICATE ? NAVAID_LINK_ACK_DUPLICATE : NAVAID_LINK_ACK_STALE;
}

static void on_frame(void* ctx, const navaid_link_frame* f) {
  navaid_link_device* dev = (navaid_link_device*)ctx;
  const int known = length_fits_type(f->type, f->len);
  /* Any frame with a valid CRC shows that the host is there. */
  dev->last_valid_ms = dev->now_ms;
  dev->link_alive = 1;
  if (known < 0) {
    /* A device-to-host type can only be our own reply coming back (a host tty left with echo
     * on): NAKing it would echo back too and loop at line rate. Only host types are refused. */
    if (f->type < 0x80u) send_nak(dev, f->seq, NAVAID_LINK_NAK_UNKNOWN_TYPE, f->type);
    return;
  }
  if (f->type == NAVAID_LINK_PATTERN && (size_t)f->payload[1] * NAVAID_LINK_ACTUATOR_SIZE + 2u != f->len) {
    send_nak(dev, f->seq, NAVAID_LINK_NAK_BAD_LENGTH, f->len);
    return;
  }
  switch (f->type) {
    case NAVAID_LINK_PATTERN: {
      uint8_t detail = 0;
      uint8_t reason;
      if (f->seq_status != NAVAID_LINK_SEQ_NEW) {
        send_ack(dev, f->seq, ack_status(f->seq_status));
        return;
      }
      reason = check_pattern(dev, f, &detail);
      if (reason != 0u) {
        send_nak(dev, f->seq, reason, detail);
        return;
      }
      apply_pattern(dev, f);
      send_ack(dev, f->seq, NAVAID_LINK_ACK_APPLIED);
      return;
    }
    case NAVAID_LINK_ALL_OFF:
      if (f->seq_status != NAVAID_LINK_SEQ_NEW) {
        send_ack(dev, f->seq, ack_status(f->seq_status));
        return;
      }
      all_off(dev);
      ++dev->counters.all_off_commands;
      send_ack(dev, f->seq, NAVAID_LINK_ACK_APPLIED);
      return;
    case NAVAID_LINK_HEARTBEAT: {
      uint8_t p[NAVAID_LINK_HEARTBEAT_REPLY_SIZE];
      put_u16(p, f->seq);
      p[2] = dev->device_kind;
      p[3] = navaid_link_device_active_mask(dev);
      put_u16(p + 4, (uint16_t)(dev->dec.counters.frames_ok & 0xFFFFu));
      put_u16(p + 6, (uint16_t)(dev->dec.counters.crc_errors & 0xFFFFu));
      ++dev->counters.heartbeats;
      queue_reply(dev, NAVAID_LINK_HEARTBEAT_REPLY, p, sizeof p);
      return;
    }
    default:
      return;
  }
}

void navaid_link_device_init(navaid_link_device* dev, uint8_t device_kind, uint8_t actuator_count,
                             uint32_t link_timeout_ms, uint32_t now_ms) {
  memset(dev, 0, sizeof *dev);
  navaid_link_decoder_init(&dev->dec);
  dev->device_kind = device_kind;
  if (actuator_count < 1u) actuator_count = 1u;
  if (actuator_count > NAVAID_LINK_MAX_ACTUATORS) actuator_count = NAVAID_LINK_MAX_ACTUATORS;
  dev->actuator_count = actuator_count;
  dev->link_timeout_ms = link_timeout_ms == 0u ? NAVAID_LINK_DEFAULT_TIMEOUT_MS : link_timeout_ms;
  dev->now_ms = now_ms;
  dev->last_valid_ms = now_ms;
  dev->last_byte_ms = now_ms;
}

void navaid_link_device_tick(navaid_link_device* dev, uint32_t now_ms) {
  dev->now_ms = now_ms;
  if (dev->dec.n > 0u && now_ms - dev->last_byte_ms > NAVAID_LINK_INTERBYTE_TIMEOUT_MS) {
    navaid_link_decoder_flush(&dev->dec, on_frame, dev);
  }
  if (dev->link_alive && now_ms - dev->last_valid_ms >= dev->link_timeout_ms) {
    all_off(dev);
    dev->link_alive = 0;
    ++dev->counters.link_timeouts;
    /* A host that comes back may have restarted its numbering. */
    navaid_link_decoder_forget_sequence(&dev->dec);
  }
  update_outputs(dev);
}

void navaid_link_device_rx(navaid_link_device* dev, const uint8_t* data, size_t n, uint32_t now_ms) {
  navaid_link_device_tick(dev, now_ms);
  if (n == 0u) return;
  navaid_link_decoder_feed(&dev->dec, data, n, on_frame, dev);
  dev->last_byte_ms = now_ms;
}

size_t navaid_link_device_tx(navaid_link_device* dev, uint8_t* out, size_t cap) {
  size_t k = 0;
  while (k < cap && dev->tx_len > 0u) {
    out[k++] = dev->tx[dev->tx_head];
    dev->tx_head = (uint16_t)((dev->tx_head + 1u) % NAVAID_LINK_TX_BUFFER);
    --dev->tx_len;
  }
  return k;
}

int16_t navaid_link_device_output(const navaid_link_device* dev, uint8_t index) {
  return index < dev->actuator_count ? dev->out[index] : (int16_t)0;
}

uint8_t navaid_link_device_active_mask(const navaid_link_device* dev) {
  uint8_t mask = 0;
  uint8_t i;
  for (i = 0; i < dev->actuator_count; ++i) {
    if (dev->act[i].active) mask = (uint8_t)(mask | (1u << i));
  }
  return mask;
}
