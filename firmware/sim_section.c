/* simavr reads the CPU frequency and supply/reference voltages of the image from this .mmcu
 * section, so a harness cannot run the firmware at the wrong clock or with the ADC's default
 * 3.3 V reference. The section is not loaded on a real device (the .hex omits it).
 * C, not C++: the AVR_MCU macros use C99 designated initialisers. */
#include <avr/avr_mcu_section.h>

AVR_MCU(F_CPU, HOTEND_MCU);
AVR_MCU_VOLTAGES(5000, 5000, 5000); /* Vcc, AVcc (the ADC reference on both boards), AREF */
