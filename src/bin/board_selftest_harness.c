/* simavr harness for the board self-test firmware (board_selftest.rs).
 *
 * Build:  cc -O2 -o /tmp/board_harness src/bin/board_selftest_harness.c \
 *             -I/usr/include/simavr -lsimavr -lelf
 * Run:    /tmp/board_harness <board-selftest.elf>
 *
 * What it adds to a plain `simavr` run:
 * - A 4-wire panel model on the ADC. At every conversion start it reads the
 *   DDR/PORT bits of the four panel pins of the wiring the firmware announces
 *   in GPIOR0 (1..3 = (a)..(c), bit 7 = untouched), checks that they form one
 *   of the three legal drive patterns (X, Y, pressure; floating pins without
 *   pull-up), that the converted channel is the one that pattern is read on,
 *   and that LCD CS/RD/WR are held inactive when the wiring does not use
 *   them. It then feeds the voltage a panel touched at a known point would
 *   give (plates 600 ohm, contact 1000 ohm).
 * - Outside touch reads it feeds fixed voltages per channel and logs the
 *   multiplexer source simavr decoded (checks MUX5 for ADC8..15).
 * - It types "hello board\n" after the firmware's "echo>" prompt and 200
 *   bytes (0..199) at line rate after "flood>".
 * Exit status 0 only if the firmware reports "selftest done fails=0" after a
 * watchdog reset and the panel model saw no violation.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_irq.h"
#include "sim_io.h"
#include "avr_adc.h"
#include "avr_uart.h"

#define GPIOR0 0x3E
/* Data-space address of PINx; DDRx = +1, PORTx = +2. */
#define PE 0x2C
#define PF 0x2F
#define PG 0x32
#define PH 0x100

typedef struct { int base, bit, ch; } pin_t;
typedef struct { pin_t xp, xm, yp, ym; double fx, fy; } wiring_t;

static const pin_t D6 = {PH, 3, -1}, D7 = {PH, 4, -1}, D8 = {PH, 5, -1}, D9 = {PH, 6, -1};
static const pin_t A0 = {PF, 0, 0}, A1 = {PF, 1, 1}, A2 = {PF, 2, 2}, A3 = {PF, 3, 3};

/* (a), (b), (c) of SPEC §8, each touched at its own point (fractions of the
 * plate, measured from XM resp. YM). */
static wiring_t wirings[3];

static avr_t *avr;
static avr_irq_t *adc_irq, *uart_in;
static int violations, touch_convs, boots;
static char line[256];
static int line_len;
static const char *tx_data;
static int tx_len, tx_pos;
static unsigned char flood[200];
static avr_cycle_count_t tx_next;
static int done_ok, fail_lines;

enum mode { M_X, M_Y, M_Z, M_BAD };

/* 0 floating, 1 pull-up, 2 out low, 3 out high */
static int pin_state(pin_t p)
{
	int ddr = (avr->data[p.base + 1] >> p.bit) & 1;
	int port = (avr->data[p.base + 2] >> p.bit) & 1;
	return ddr * 2 + port;
}

static int same(pin_t a, pin_t b) { return a.base == b.base && a.bit == b.bit; }

static enum mode classify(const wiring_t *w)
{
	int xp = pin_state(w->xp), xm = pin_state(w->xm), yp = pin_state(w->yp), ym = pin_state(w->ym);
	if (xp == 3 && xm == 2 && yp == 0 && ym == 0) return M_X;
	if (yp == 3 && ym == 2 && xp == 0 && xm == 0) return M_Y;
	if (xp == 2 && ym == 3 && xm == 0 && yp == 0) return M_Z;
	printf("[harness] VIOLATION pins xp=%d xm=%d yp=%d ym=%d\n", xp, xm, yp, ym);
	return M_BAD;
}

static void check_idle(const wiring_t *w, pin_t p, const char *name)
{
	if (same(p, w->xp) || same(p, w->xm) || same(p, w->yp) || same(p, w->ym))
		return;
	if (pin_state(p) != 3) {
		printf("[harness] VIOLATION %s not held high during touch (state %d)\n", name, pin_state(p));
		violations++;
	}
}

static void adc_trigger(struct avr_irq_t *irq, uint32_t value, void *param)
{
	union { avr_adc_mux_t mux; uint32_t v; } u = { .v = value };
	int src = u.mux.src;
	int g = avr->data[GPIOR0];
	(void)irq; (void)param;
	if (g == 0) {
		static const int mv[16] = {1000, 0, 0, 0, 0, 2500, 0, 0, 3000, 0, 0, 0, 0, 0, 0, 4000};
		printf("[harness] adc kind=%d src=%d\n", u.mux.kind, src);
		if (u.mux.kind == ADC_MUX_SINGLE && src < 8)
			avr_raise_irq(adc_irq + src, mv[src]);
		return;
	}
	int wi = (g & 0x7f) - 1;
	int touched = !(g & 0x80);
	if (wi < 0 || wi > 2) {
		printf("[harness] bad GPIOR0 %d\n", g);
		violations++;
		return;
	}
	const wiring_t *w = &wirings[wi];
	touch_convs++;
	check_idle(w, A3, "CS");
	check_idle(w, A0, "RD");
	check_idle(w, A1, "WR");
	enum mode m = classify(w);
	double Rx = 600, Ry = 600, Rt = 1000, v = 0;
	if (m == M_X) {
		if (src != w->yp.ch) { printf("[harness] VIOLATION X read on ch %d\n", src); violations++; }
		v = touched ? 5000 * w->fx : 0;
	} else if (m == M_Y) {
		if (src != w->xm.ch) { printf("[harness] VIOLATION Y read on ch %d\n", src); violations++; }
		v = touched ? 5000 * w->fy : 0;
	} else if (m == M_Z) {
		double rx = Rx * (1 - w->fx), ry = Ry * w->fy, i = 5000 / (rx + Rt + ry);
		if (src == w->xm.ch) v = touched ? i * rx : 0;          /* z1 */
		else if (src == w->yp.ch) v = touched ? 5000 - i * ry : 5000; /* z2 */
		else { printf("[harness] VIOLATION Z read on ch %d\n", src); violations++; }
	} else {
		violations++;
	}
	avr_raise_irq(adc_irq + src, (uint32_t)(v + 0.5));
}

static void start_tx(const unsigned char *d, int n)
{
	tx_data = (const char *)d;
	tx_len = n;
	tx_pos = 0;
	tx_next = avr->cycle + 16000; /* 1 ms after the prompt */
}

static void uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
	(void)irq; (void)param;
	char c = (char)value;
	if (c == '\n' || line_len == (int)sizeof(line) - 1) {
		line[line_len] = 0;
		printf("%s\n", line);
		if (!strncmp(line, "selftest mcusr=", 15)) boots++;
		if (!strcmp(line, "echo>")) start_tx((const unsigned char *)"hello board\n", 12);
		if (!strcmp(line, "flood>")) start_tx(flood, sizeof flood);
		if (strstr(line, "FAIL")) fail_lines++;
		if (!strcmp(line, "selftest done fails=0")) done_ok = 1;
		line_len = 0;
	} else {
		line[line_len++] = c;
	}
}

int main(int argc, char **argv)
{
	elf_firmware_t fw;
	setvbuf(stdout, NULL, _IOLBF, 0);
	memset(&fw, 0, sizeof fw);
	if (argc < 2 || elf_read_firmware(argv[1], &fw)) {
		fprintf(stderr, "usage: %s firmware.elf\n", argv[0]);
		return 2;
	}
	wiring_t a = {D8, A2, A3, D9, 0.25, 0.75}, b = {D6, A2, A1, D7, 0.5, 0.2}, c = {D7, A1, A2, D6, 0.8, 0.4};
	wirings[0] = a; wirings[1] = b; wirings[2] = c;
	for (int i = 0; i < 200; i++) flood[i] = (unsigned char)i;

	avr = avr_make_mcu_by_name("atmega2560");
	if (!avr) return 2;
	avr_init(avr);
	fw.frequency = 16000000;
	avr_load_firmware(avr, &fw);
	avr->frequency = 16000000;
	avr->vcc = avr->avcc = avr->aref = 5000;

	uint32_t flags = 0;
	avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
	/* No console echo; no host usleep while the firmware polls UCSR0A. */
	flags &= ~(AVR_UART_FLAG_STDIO | AVR_UART_FLAG_POLL_SLEEP);
	avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
	avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), uart_out, NULL);
	uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
	adc_irq = avr_io_getirq(avr, AVR_IOCTL_ADC_GETIRQ, 0);
	avr_irq_register_notify(adc_irq + ADC_IRQ_OUT_TRIGGER, adc_trigger, NULL);

	int state = cpu_Running;
	const avr_cycle_count_t limit = 16000000ull * 10;
	while (state != cpu_Done && state != cpu_Crashed && avr->cycle < limit) {
		if (tx_data && tx_pos < tx_len && avr->cycle >= tx_next) {
			avr_raise_irq(uart_in, (unsigned char)tx_data[tx_pos++]);
			tx_next = avr->cycle + 1389; /* one 10-bit frame at 115200 baud */
		}
		state = avr_run(avr);
	}
	printf("[harness] end state=%d t=%.3f s boots=%d touch_conversions=%d violations=%d fail_lines=%d\n",
	       state, avr->cycle / 16e6, boots, touch_convs, violations, fail_lines);
	int ok = done_ok && boots == 2 && violations == 0 && fail_lines == 0 && touch_convs > 0;
	printf("[harness] %s\n", ok ? "PASS" : "FAIL");
	return ok ? 0 : 1;
}
