/*
 * A session's clock exchanges with the laptop it was linked to (docs/SYNC.md), in their own file
 * clock.csv: one row per whole exchange, the laptop's times on its monotonic clock (named in
 * meta.json's `clock_link`), the phone's on its sensor clock (the clock of every timestamp here).
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import dev.motionfusion.core.sync.ClockExchange

public object SessionClock {
    public const val FILE_NAME: String = "clock.csv"
    public const val HEADER: String = "laptop_sent_ns,phone_received_ns,phone_replied_ns,laptop_received_ns"

    /** More rows than ten days of exchanges at 4 Hz is not a recording's clock file. */
    public const val MAX_EXCHANGES: Int = 4_000_000

    /** One row of clock.csv for [e], with its newline. */
    @JvmStatic
    public fun row(e: ClockExchange): String = "${e.t1},${e.t2},${e.t3},${e.t4}\n"

    /** The exchanges of a clock.csv read by [csv] (an unterminated last line skipped when [skipCutLastLine]). */
    internal fun read(csv: ByteCsvReader, skipCutLastLine: Boolean): List<ClockExchange> = csv.use {
        val header = csv.header(HEADER)
        val columns = HEADER.split(',').map { header.require(it) }
        val out = ArrayList<ClockExchange>()
        val t = LongArray(4)
        while (csv.nextRecord(skipCutLastLine)) {
            if (out.size == MAX_EXCHANGES) throw DataFormatException(csv.sourceName, csv.lineNumber, 1, "more than $MAX_EXCHANGES clock exchanges")
            for (k in 0 until 4) {
                try {
                    t[k] = csv.parseLong(columns[k])
                } catch (e: FieldError) {
                    throw csv.error(columns[k], "column ${HEADER.split(',')[k]}: ${e.reason}")
                }
            }
            out += ClockExchange(t[0], t[1], t[2], t[3])
        }
        out
    }
}
