/*
 * The plain IMU table: one CSV row per instant with every sensor sampled together.
 *
 *     t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]
 *
 * t_s in seconds, gyroscope in rad/s, accelerometer in m/s² (specific force: +9.81 on the
 * up axis at rest, as Android's TYPE_ACCELEROMETER), magnetometer in µT, all in the device
 * frame. Columns are found by name, so their order is free and extra columns are ignored; every
 * row has the header's number of fields. A magnetometer field may be empty (no reading at that
 * instant); other fields may not. Numbers use '.' as decimal separator; NaN and Infinity are
 * read as such (the filter skips them), but t_s must be finite. The file may be
 * gzip-compressed. Reading streams: memory does not grow with the file.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.CompressionGuard
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import dev.motionfusion.core.io.InputLimits
import dev.motionfusion.core.io.Inputs
import dev.motionfusion.core.event.RowEvents
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import java.io.Closeable
import java.io.InputStream
import java.util.concurrent.ArrayBlockingQueue
import java.nio.file.Path
import kotlin.math.roundToLong

/**
 * A cursor over the rows of an IMU table: call [next] and, while it returns true, read [timeS]
 * and [row] (reused by the next call). Malformed content throws [DataFormatException] naming the
 * source, line and column.
 */
public class ImuTableReader internal constructor(private val csv: ByteCsvReader) : Closeable {
    /** True when the table has magnetometer columns. */
    public val hasMagnetometer: Boolean

    /** Time of the current row, s. */
    public var timeS: Double = Double.NaN
        private set

    /** The current row: gx, gy, gz (rad/s), ax, ay, az (m/s²), mx, my, mz (µT; NaN when absent). */
    public val row: DoubleArray = DoubleArray(9) { Double.NaN }

    private val index = IntArray(COLUMNS.size) { -1 }
    private val fieldCount: Int

    /** Field → column (index into COLUMNS), −1 for the columns ignored; and the values of a plain row by column. */
    private val slot: IntArray
    private val parsed = DoubleArray(COLUMNS.size) { Double.NaN }

    init {
        try {
            val names = csv.header(COLUMNS.joinToString(",")).names.map { it.lowercase() }
            fieldCount = names.size
            for ((i, n) in names.withIndex()) {
                val c = COLUMNS.indexOf(n)
                if (c >= 0) {
                    if (index[c] >= 0) throw DataFormatException(csv.sourceName, 1, csv.column(i), "column $n appears twice")
                    index[c] = i
                }
            }
            val missing = COLUMNS.take(REQUIRED).filterIndexed { c, _ -> index[c] < 0 }
            if (missing.isNotEmpty()) {
                throw DataFormatException(csv.sourceName, 1, 1,
                    "header lacks column(s) ${missing.joinToString(",")}; expected ${COLUMNS.joinToString(",")} (magnetometer optional)")
            }
            val magPresent = (REQUIRED until COLUMNS.size).count { index[it] >= 0 }
            if (magPresent in 1 until COLUMNS.size - REQUIRED) {
                throw DataFormatException(csv.sourceName, 1, 1, "header has only some of mx,my,mz: give all three or none")
            }
            hasMagnetometer = magPresent > 0
            slot = IntArray(fieldCount) { i -> index.indexOf(i) }
        } catch (e: Throwable) {
            csv.close()
            throw e
        }
    }

    // Rows read, and those with a magnetometer reading (a table whose magnetometer never reads is refused at its end).
    private var rows = 0L
    private var magnetometerRows = 0L

    /** Advances to the next row; false at the end. */
    public fun next(): Boolean {
        if (!advance()) {
            if (hasMagnetometer && rows > 0 && magnetometerRows == 0L) {
                throw DataFormatException(csv.sourceName, 0, 0, "mx,my,mz are empty in every row: the magnetometer never reads; leave the columns out (a 6D recording)")
            }
            return false
        }
        rows++
        if (hasMagnetometer && hasMagnetometerReading(row)) magnetometerRows++
        return true
    }

    private fun advance(): Boolean {
        when (csv.nextRow(fieldCount, slot, parsed)) {
            ByteCsvReader.END -> return false
            ByteCsvReader.ROW -> {
                // A plain row, parsed in one pass: the same doubles as the general path below.
                timeS = try {
                    csv.checkedTimeS(parsed[0], index[0])
                } catch (e: FieldError) {
                    throw csv.error(index[0], "column t_s: ${e.reason}")
                }
                parsed.copyInto(row, 0, 1, COLUMNS.size)
                return true
            }
        }
        csv.requireFieldCount()
        var c = 0
        try {
            timeS = csv.parseTimeS(index[0])
            c = 1
            while (c < COLUMNS.size) {
                val i = index[c]
                if (i >= 0) row[c - 1] = csv.parseDouble(i, emptyIsNaN = c >= REQUIRED)
                c++
            }
        } catch (e: FieldError) {
            throw csv.error(index[c], "column ${COLUMNS[c]}: ${e.reason}")
        }
        return true
    }

    override fun close(): Unit = csv.close()

    public companion object {
        /** Column names in canonical order; the first [REQUIRED] are mandatory. */
        internal val COLUMNS: List<String> = listOf("t_s", "gx", "gy", "gz", "ax", "ay", "az", "mx", "my", "mz")
        private const val REQUIRED = 7


        /**
         * Whether [row] (gx … mz, as [row]) holds a magnetometer reading: its three fields empty (NaN) mean none at that
         * instant, a magnetometer slower than the table's rows (docs/IMPORT.md); one or two empty is a reading that
         * is not finite, which the filter skips and counts.
         */
        internal fun hasMagnetometerReading(row: DoubleArray): Boolean = !(row[6].isNaN() && row[7].isNaN() && row[8].isNaN())

        /** True when [header] (a first line) names the required columns of an IMU table. */
        internal fun recognises(header: String): Boolean {
            val names = ByteCsvReader.headerNames(header).map { it.lowercase() }
            return COLUMNS.take(REQUIRED).all { it in names }
        }

        /** Opens [path] (plain or gzip). The caller closes the reader. */
        @JvmStatic
        @JvmOverloads
        public fun open(path: Path, limits: InputLimits = InputLimits()): ImuTableReader =
            open(Inputs.openFile(path), Inputs.shown(path), limits)

        /** Reads from [input] (plain or gzip); [sourceName] names it in errors. */
        @JvmStatic
        @JvmOverloads
        public fun open(input: InputStream, sourceName: String, limits: InputLimits = InputLimits()): ImuTableReader =
            ImuTableReader(ByteCsvReader(Inputs.maybeGunzip(input, sourceName, CompressionGuard(limits)), sourceName))
    }
}

/**
 * The plain IMU table as events: per row accelerometer, magnetometer (if any), then gyroscope,
 * all at t_s. With [ahead], the rows are parsed on a second thread in batches of fixed size while
 * the caller filters the previous ones: the same rows in the same order, an error thrown when the
 * caller reaches the row where it occurred, memory flat (three batches).
 */
internal class ImuTableEvents(private val table: ImuTableReader, ahead: Boolean = false) : RowEvents {
    private var phase = 3
    override var stream: SessionStream = SessionStream.ACCELEROMETER
        private set
    override var timestampNs: Long = 0L
        private set
    override val values: DoubleArray = DoubleArray(3)
    override val accuracy: Int get() = SensorEvents.NO_ACCURACY
    override val hasMagnetometer: Boolean = table.hasMagnetometer
    private val prefetch: Prefetch? = if (ahead) Prefetch() else null
    override val row: DoubleArray = prefetch?.row ?: table.row

    override fun nextRow(): Boolean {
        val p = prefetch
        val t: Double
        if (p != null) {
            if (!p.next()) return false
            t = p.timeS
        } else {
            if (!table.next()) return false
            t = table.timeS
        }
        timestampNs = (t * 1e9).roundToLong()
        return true
    }

    override fun next(): Boolean {
        val r = row
        while (true) {
            when (phase) {
                0 -> { phase = 1; stream = SessionStream.ACCELEROMETER; values[0] = r[3]; values[1] = r[4]; values[2] = r[5]; return true }
                1 -> {
                    phase = 2
                    if (hasMagnetometer && ImuTableReader.hasMagnetometerReading(r)) {
                        stream = SessionStream.MAGNETOMETER; values[0] = r[6]; values[1] = r[7]; values[2] = r[8]; return true
                    }
                }
                2 -> { phase = 3; stream = SessionStream.GYROSCOPE; values[0] = r[0]; values[1] = r[1]; values[2] = r[2]; return true }
                else -> {
                    if (!nextRow()) return false
                    phase = 0
                }
            }
        }
    }

    override fun close() {
        prefetch?.stop()
        table.close()
    }

    /** Rows of [table] read by a second thread into batches of t_s and the 9 values. */
    private inner class Prefetch {
        val row = DoubleArray(9)
        var timeS = Double.NaN
        private val free = ArrayBlockingQueue<Batch>(3)
        private val full = ArrayBlockingQueue<Batch>(3)
        private var current: Batch? = null
        private var index = 0
        private val thread = Thread(::loop, "table-reader").apply { isDaemon = true }

        init {
            repeat(3) { free.add(Batch()) }
            thread.start()
        }

        fun next(): Boolean {
            var b = current
            if (b == null || index == b.count) {
                if (b != null) {
                    if (b.end) return b.finish()
                    free.put(b)
                }
                b = full.take()
                current = b
                index = 0
                if (b.count == 0) return b.finish()
            }
            val o = index++ * STRIDE
            timeS = b.data[o]
            b.data.copyInto(row, 0, o + 1, o + STRIDE)
            return true
        }

        private fun Batch.finish(): Boolean {
            count = 0
            index = 0
            error?.let { error = null; throw it }
            return false
        }

        private fun loop() {
            try {
                while (true) {
                    val b = free.take()
                    b.count = 0
                    try {
                        while (b.count < ROWS && table.next()) {
                            val o = b.count++ * STRIDE
                            b.data[o] = table.timeS
                            table.row.copyInto(b.data, o + 1, 0, 9)
                        }
                        b.end = b.count < ROWS
                    } catch (e: Throwable) {
                        b.error = e
                        b.end = true
                    }
                    full.put(b)
                    if (b.end) return
                }
            } catch (e: InterruptedException) {
                // stopped by close()
            }
        }

        fun stop() {
            thread.interrupt()
            thread.join()
        }
    }

    private class Batch {
        val data = DoubleArray(ROWS * STRIDE)
        var count = 0
        var end = false
        var error: Throwable? = null
    }

    private companion object {
        const val ROWS = 4096
        const val STRIDE = 10
    }
}
