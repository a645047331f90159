/*
 * Markers of a session (docs/SESSION_FORMAT.md, "Markers"): moments the user marked while
 * recording, with an optional short text, in their own file markers.csv:
 *
 *   timestamp_ns,label
 *   8130000000000,"start walking"
 *   8131500000000,"stairs, ""up"""
 *
 * The label is always written quoted, a quote inside it doubled (RFC 4180); it is one line of
 * at most MAX_LABEL_CHARS characters (control characters, line ends included, become spaces).
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import java.io.Closeable

/** A moment marked during recording: [timestampNs] on the sensor clock (SystemClock.elapsedRealtimeNanos), [label] (may be empty). */
public data class Marker(val timestampNs: Long, val label: String)

/** The markers stream: file, header and the rules of its labels. */
public object SessionMarkers {
    /** File name inside the session folder. */
    public const val FILE_NAME: String = "markers.csv"

    /** The stream's name in meta.json's `streams`. */
    public const val KEY: String = "markers"

    /** The header line, without newline. */
    public const val HEADER: String = "timestamp_ns,label"

    /** Longest label, in UTF-16 characters; the writer cuts longer ones, readers refuse them. */
    public const val MAX_LABEL_CHARS: Int = 200

    /** More markers than this in one session is not a recording's (readers refuse, memory stays bounded). */
    public const val MAX_MARKERS: Int = 100_000

    /**
     * [text] as it is stored: control characters (line ends, tabs) replaced by spaces, unpaired
     * surrogates by U+FFFD, surrounding spaces trimmed, cut to [MAX_LABEL_CHARS] without splitting a
     * surrogate pair.
     */
    @JvmStatic
    public fun label(text: String): String {
        val sb = StringBuilder(minOf(text.length, MAX_LABEL_CHARS + 1))
        var i = 0
        while (i < text.length && sb.length < 4 * MAX_LABEL_CHARS) {
            val c = text[i]
            when {
                Character.isHighSurrogate(c) && i + 1 < text.length && Character.isLowSurrogate(text[i + 1]) -> {
                    sb.append(c).append(text[i + 1])
                    i++
                }
                c.isSurrogate() -> sb.append('\uFFFD')
                c < ' ' || c in '\u007f'..'\u009f' || c == '\u2028' || c == '\u2029' -> sb.append(' ')
                else -> sb.append(c)
            }
            i++
        }
        val trimmed = sb.trim()
        if (trimmed.length <= MAX_LABEL_CHARS) return trimmed.toString()
        val end = if (Character.isHighSurrogate(trimmed[MAX_LABEL_CHARS - 1])) MAX_LABEL_CHARS - 1 else MAX_LABEL_CHARS
        return trimmed.substring(0, end).trimEnd()
    }

    /** One row of markers.csv for [label] (already passed through [label]), with its newline. */
    internal fun row(timestampNs: Long, label: String): ByteArray =
        "$timestampNs,\"${label.replace("\"", "\"\"")}\"\n".toByteArray(Charsets.UTF_8)
}

/** Reads markers.csv row by row: the timestamp as an integer, the label as strict UTF-8 of at most the maximum length. */
internal class MarkerCursor(private val csv: ByteCsvReader, private val skipCutLastLine: Boolean) : Closeable {
    var timestampNs: Long = 0L
        private set
    var label: String = ""
        private set

    private val timeIndex: Int
    private val labelIndex: Int

    init {
        try {
            val header = csv.header(SessionMarkers.HEADER)
            timeIndex = header.require(SessionStream.TIMESTAMP_COLUMN)
            labelIndex = header.require("label")
        } catch (e: Throwable) {
            csv.close()
            throw e
        }
    }

    /** The next marker; false at the end. @throws DataFormatException at the malformed field's line and column. */
    fun next(): Boolean {
        if (!csv.nextRecord(skipCutLastLine)) return false
        var field = timeIndex
        try {
            timestampNs = csv.parseLong(field)
            field = labelIndex
            val text = csv.unquotedText(field)
            if (text.length > SessionMarkers.MAX_LABEL_CHARS) {
                throw FieldError("label of ${text.length} characters, longer than ${SessionMarkers.MAX_LABEL_CHARS}")
            }
            label = SessionMarkers.label(text)
        } catch (e: FieldError) {
            throw csv.error(field, "column ${if (field == timeIndex) SessionStream.TIMESTAMP_COLUMN else "label"}: ${e.reason}")
        }
        return true
    }

    /** Every remaining marker, at most [SessionMarkers.MAX_MARKERS]. */
    fun readAll(): List<Marker> {
        val out = ArrayList<Marker>()
        while (next()) {
            if (out.size == SessionMarkers.MAX_MARKERS) {
                throw DataFormatException(csv.sourceName, csv.lineNumber, 1, "more than ${SessionMarkers.MAX_MARKERS} markers: not a recording's markers")
            }
            out += Marker(timestampNs, label)
        }
        return out
    }

    override fun close(): Unit = csv.close()
}
