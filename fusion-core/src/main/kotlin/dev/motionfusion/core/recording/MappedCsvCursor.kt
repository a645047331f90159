/*
 * One stream of another app's export: a CSV whose columns are found by name, with its own
 * separator and decimal mark, a time column in s or ns, and value columns with unit factors to
 * SI. Produces SessionStream events (Android device frame, SI units).
 */
package dev.motionfusion.core.recording

import dev.motionfusion.core.io.CsvLine
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import dev.motionfusion.core.session.SessionEvents
import dev.motionfusion.core.session.SessionStream
import dev.motionfusion.core.session.StreamCursor
import java.io.BufferedReader
import kotlin.math.roundToLong

/** A CSV dialect: field [separator] and whether numbers use a decimal comma. */
internal data class Dialect(val separator: Char, val decimalComma: Boolean) {
    companion object {
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

/**
 * @param timeIndex field of the time column; [timeToNs] its factor to ns (1e9 for seconds).
 * @param valueIndex field of each of [stream]'s values, −1 for "not in this export" (NaN).
 * @param valueScale factor from each column's unit to the stream's SI unit.
 */
internal class MappedCsvCursor(
    override val stream: SessionStream,
    private val reader: BufferedReader,
    private val sourceName: String,
    private val dialect: Dialect,
    private val timeIndex: Int,
    private val timeToNs: Double,
    private val valueIndex: IntArray,
    private val valueScale: DoubleArray,
    private val firstLineNumber: Long,
) : StreamCursor {
    override var timestampNs: Long = 0L
        private set
    override val values: DoubleArray = DoubleArray(stream.valueCount)
    override val accuracy: Int = if (stream.hasAccuracy) UNKNOWN_ACCURACY else SessionEvents.NO_ACCURACY
    private val fields = CsvLine(dialect.separator)
    private var lineNumber = firstLineNumber
    private val needed = maxOf(timeIndex, valueIndex.maxOrNull() ?: 0) + 1

    override fun next(): Boolean {
        var line: String
        while (true) {
            line = reader.readLine() ?: return false
            lineNumber++
            if (line.isNotBlank()) break
        }
        if (line.length > MAX_LINE_CHARS) throw DataFormatException(sourceName, lineNumber, 0, "line longer than $MAX_LINE_CHARS characters")
        val text = if (dialect.decimalComma) line.replace(',', '.') else line
        fields.split(text)
        if (fields.count < needed) {
            throw DataFormatException(sourceName, lineNumber, line.length + 1, "row has ${fields.count} fields, expected at least $needed")
        }
        var field = timeIndex
        try {
            val exactNs = if (timeToNs == 1.0) fields.text(timeIndex).trim().toLongOrNull() else null
            if (exactNs != null) {
                timestampNs = exactNs
            } else {
                val t = fields.parseDouble(timeIndex, emptyIsNaN = false) * timeToNs
                if (!(kotlin.math.abs(t) < 9.2e18)) throw FieldError("time ${fields.text(timeIndex)} is not a finite time")
                timestampNs = t.roundToLong()
            }
            for (k in valueIndex.indices) {
                val i = valueIndex[k]
                field = i
                values[k] = if (i < 0) Double.NaN else fields.parseDouble(i, emptyIsNaN = true) * valueScale[k]
            }
        } catch (e: FieldError) {
            throw DataFormatException(sourceName, lineNumber, fields.start(field) + 1, e.reason)
        }
        return true
    }

    override fun close(): Unit = reader.close()

    companion object {
        /** Exports carry no per-event accuracy: their events report NO_ACCURACY. */
        const val UNKNOWN_ACCURACY: Int = SessionEvents.NO_ACCURACY
        const val MAX_LINE_CHARS: Int = 1 shl 20
    }
}
