/*
 * One stream of another app's export: a CSV whose columns are found by name, with its own
 * separator and decimal mark, a time column in s or integer ns, and value columns with factors
 * to SI. Produces SessionStream events (Android device frame, SI units).
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.FieldError
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.event.StreamCursor
import dev.motionfusion.core.WorldFrame
import kotlin.math.roundToLong

/** A CSV dialect: field [separator] and whether numbers may use a decimal comma. */
internal data class Dialect(val separator: Char, val decimalComma: Boolean) {
    companion object {
        val COMMA = Dialect(',', false)

        /**
         * The dialect of a file from its header line: the most frequent of tab, semicolon and
         * comma outside quotes is the separator; with a separator other than comma, numbers may
         * use a decimal comma (phyphox offers both).
         */
        fun detect(header: String): Dialect {
            var inQuotes = false
            var tabs = 0
            var semis = 0
            var commas = 0
            for (c in header) {
                when {
                    c == '"' -> inQuotes = !inQuotes
                    inQuotes -> Unit
                    c == '\t' -> tabs++
                    c == ';' -> semis++
                    c == ',' -> commas++
                }
            }
            val sep = when {
                tabs >= semis && tabs >= commas && tabs > 0 -> '\t'
                semis >= commas && semis > 0 -> ';'
                else -> ','
            }
            return Dialect(sep, sep != ',')
        }
    }
}

/** Where a stream's values are in an export's CSV and how they convert to SI. */
internal class ColumnMap(
    val stream: SessionStream,
    val path: String,
    val dialect: Dialect,
    /** Field of the time column. */
    val timeIndex: Int,
    /** True when time is integer nanoseconds (Sensor Logger), false for seconds (phyphox). */
    val timeIsNs: Boolean,
    /** Field of each of [stream]'s values, −1 for "not in this export" (NaN). */
    val valueIndex: IntArray,
    /** Factor from each column's unit (and sign convention) to the stream's. */
    val valueScale: DoubleArray,
    /** The end of the recording where the export states it (phyphox meta/time.csv), s; later rows belong to another. */
    val endS: Double = Double.POSITIVE_INFINITY,
) {
    fun open(files: FileSet): StreamCursor = ExportCsvCursor(this, files.csv(path, dialect.separator.code.toByte(), dialect.decimalComma))
}

internal class ExportCsvCursor(private val map: ColumnMap, private val csv: ByteCsvReader) : StreamCursor {
    override val stream: SessionStream get() = map.stream
    override var timestampNs: Long = 0L
        private set
    override val values: DoubleArray = DoubleArray(map.stream.valueCount)
    override val accuracy: Int = SensorEvents.NO_ACCURACY
    init {
        try {
            csv.header(null)
        } catch (e: Throwable) {
            csv.close()
            throw e
        }
    }

    override fun next(): Boolean {
        if (!csv.nextRecord()) return false
        var field = map.timeIndex
        try {
            if (map.timeIsNs) {
                timestampNs = try {
                    csv.parseLong(field)
                } catch (e: FieldError) {
                    throw FieldError("${e.reason}: the time column holds integer nanoseconds (a re-saved file that wrote them as decimals loses their precision)")
                }
            } else {
                val t = csv.parseTimeS(field)
                if (t > map.endS + END_TOLERANCE_S) {
                    throw FieldError("time $t s is after the end of the experiment (${map.endS} s, meta/time.csv): this file belongs to another recording")
                }
                timestampNs = (t * 1e9).roundToLong()
            }
            for (k in map.valueIndex.indices) {
                val i = map.valueIndex[k]
                field = i
                values[k] = if (i < 0) Double.NaN else csv.parseDouble(i, emptyIsNaN = true) * map.valueScale[k]
            }
        } catch (e: FieldError) {
            throw csv.error(field, e.reason)
        }
        return true
    }

    override fun close(): Unit = csv.close()

    private companion object {
        const val END_TOLERANCE_S = 1.0
    }
}

/**
 * The sum of two streams sampled at the same instants (Sensor Logger's linear acceleration and
 * gravity, which iOS and Android deliver together): rows whose timestamps differ are skipped on
 * the earlier side until both agree.
 */
internal class SumCursor(private val a: StreamCursor, private val b: StreamCursor) : StreamCursor {
    override val stream: SessionStream get() = a.stream
    override val timestampNs: Long get() = a.timestampNs
    override val values: DoubleArray = DoubleArray(a.values.size)
    override val accuracy: Int get() = a.accuracy

    override fun next(): Boolean {
        if (!a.next() || !b.next()) return false
        while (a.timestampNs != b.timestampNs) {
            if (a.timestampNs < b.timestampNs) { if (!a.next()) return false } else if (!b.next()) return false
        }
        for (k in values.indices) values[k] = a.values[k] + b.values[k]
        return true
    }

    override fun close() {
        try { a.close() } finally { b.close() }
    }
}

/**
 * A rotation-vector stream ([x, y, z, w] first) whose orientations are sensor → [from], turned
 * into sensor → ENU as every reader delivers them: q_ENU = c ⊗ q with c = [from] → ENU (iOS
 * CoreMotion's x-north-z-vertical reference is NWU).
 */
internal class WorldFrameCursor(private val source: StreamCursor, from: WorldFrame) : StreamCursor {
    private val c = from.quaternionTo(WorldFrame.ENU)
    override val stream: SessionStream get() = source.stream
    override val timestampNs: Long get() = source.timestampNs
    override val values: DoubleArray = DoubleArray(source.values.size)
    override val accuracy: Int get() = source.accuracy
    private val q = DoubleArray(4)

    override fun next(): Boolean {
        if (!source.next()) return false
        val v = source.values
        c.timesInto(v[3], v[0], v[1], v[2], q, 0)
        values[0] = q[1]
        values[1] = q[2]
        values[2] = q[3]
        values[3] = q[0]
        for (k in 4 until values.size) values[k] = v[k]
        return true
    }

    override fun close(): Unit = source.close()
}
