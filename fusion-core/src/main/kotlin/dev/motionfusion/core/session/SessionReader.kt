/*
 * The reader of sessions (docs/SESSION_FORMAT.md): a folder or its zip export. Streams are read
 * lazily and merged by timestamp; memory is constant for any length.
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.event.MergedEvents
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.event.StreamCursor
import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FieldError
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.io.InputLimits
import java.io.Closeable
import java.io.IOException
import java.nio.charset.StandardCharsets
import java.nio.file.Path
import java.nio.file.Paths

/**
 * An open session. [metadata] is read at once; the streams when [events] or [stream] is called
 * (each call opens its files anew, so a session can be read several times).
 */
public class SessionReader private constructor(
    private val files: FileSet,
    /** The session's folder inside [files]: "" or ending in '/'. */
    private val dir: String,
    /** The metadata of meta.json. */
    public val metadata: SessionMetadata,
) : Closeable {

    /** The session's name: folder or zip name. */
    public val name: String = Paths.get(files.name).fileName.toString()

    /** The streams that have a file in the session. */
    public val streams: Set<SessionStream> =
        SessionStream.entries.filterTo(java.util.EnumSet.noneOf(SessionStream::class.java)) { files.paths.contains(dir + it.fileName) }

    /**
     * Events of [which] streams (default: all present) merged in time order. In a session that
     * was not closed ("complete": false) an unterminated last line of a file is skipped as cut
     * off by the interruption; in a complete session it is read like any other.
     */
    public fun events(which: Set<SessionStream> = streams): SensorEvents {
        val cursors = ArrayList<StreamCursor>()
        try {
            for (s in which) if (s in streams) cursors += cursor(s)
        } catch (e: Throwable) {
            cursors.forEach { runCatching { it.close() } }
            throw e
        }
        return MergedEvents(cursors)
    }

    /** The events of one stream in file order. */
    public fun stream(s: SessionStream): SensorEvents {
        require(s in streams) { "$name has no ${s.fileName}" }
        return MergedEvents(listOf(cursor(s)))
    }

    /** True when the session has a markers.csv. */
    public val hasMarkers: Boolean get() = files.paths.contains(dir + SessionMarkers.FILE_NAME)

    /**
     * The markers of markers.csv in file order (empty when the session has none); as for the
     * streams, an unterminated last line of an interrupted session is skipped.
     * @throws DataFormatException for a malformed row (`markers.csv:line:column: reason`), a label
     *   that is not UTF-8 or longer than [SessionMarkers.MAX_LABEL_CHARS], or more than
     *   [SessionMarkers.MAX_MARKERS] markers.
     */
    public fun markers(): List<Marker> {
        if (!hasMarkers) return emptyList()
        return MarkerCursor(files.csv(dir + SessionMarkers.FILE_NAME), skipCutLastLine = !metadata.complete).use { it.readAll() }
    }

    /**
     * The clock exchanges of clock.csv with the laptop named in meta.json's `clock_link` (empty when the session has
     * none); as for the streams, an unterminated last line of an interrupted session is skipped.
     * @throws DataFormatException for a malformed row (`clock.csv:line:column: reason`).
     */
    public fun clockExchanges(): List<dev.motionfusion.core.sync.ClockExchange> {
        if (!files.paths.contains(dir + SessionClock.FILE_NAME)) return emptyList()
        return SessionClock.read(files.csv(dir + SessionClock.FILE_NAME), skipCutLastLine = !metadata.complete)
    }

    private fun cursor(s: SessionStream): StreamCursor =
        SessionCsvCursor(s, files.csv(dir + s.fileName), skipCutLastLine = !metadata.complete)

    override fun close(): Unit = files.close()

    public companion object {
        /** meta.json larger than this is not a session's metadata (and is never read into memory). */
        private const val MAX_METADATA_BYTES = 1 shl 20

        /**
         * Opens the session folder or zip at [path]. In a zip, the session may sit at the root or
         * in one folder (the shallowest meta.json locates it).
         * @throws DataFormatException for a missing or malformed meta.json or a broken zip.
         */
        @JvmStatic
        @JvmOverloads
        public fun open(path: Path, limits: InputLimits = InputLimits()): SessionReader {
            val files = FileSet.open(path, limits)
            try {
                val meta = files.paths.firstOrNull { it == SessionMetadata.FILE_NAME || it.endsWith("/" + SessionMetadata.FILE_NAME) }
                    ?: throw DataFormatException(files.displayName(SessionMetadata.FILE_NAME), 0, 0, "missing: not a session (no meta.json)")
                return open(files, meta.removeSuffix(SessionMetadata.FILE_NAME))
            } catch (e: Throwable) {
                files.close()
                throw e
            }
        }

        /** The session in folder [dir] of [files] (which the reader then owns). */
        internal fun open(files: FileSet, dir: String): SessionReader {
            val metaPath = dir + SessionMetadata.FILE_NAME
            val text = String(files.readSmall(metaPath, MAX_METADATA_BYTES), StandardCharsets.UTF_8)
            return SessionReader(files, dir, MetadataJson.parse(text, files.displayName(metaPath)))
        }

        /** True when [path] is a folder with meta.json or a zip holding one. */
        @JvmStatic
        internal fun isSession(path: Path): Boolean = try {
            FileSet.open(path).use { f -> f.paths.any { it == SessionMetadata.FILE_NAME || it.endsWith("/" + SessionMetadata.FILE_NAME) } }
        } catch (e: IOException) {
            false
        } catch (e: DataFormatException) {
            false
        }
    }
}

/** One session CSV: header checked by column name, rows parsed from bytes. */
internal class SessionCsvCursor(
    override val stream: SessionStream,
    private val csv: ByteCsvReader,
    private val skipCutLastLine: Boolean,
) : StreamCursor {
    override var timestampNs: Long = 0L
        private set
    override val values: DoubleArray = DoubleArray(stream.valueCount)
    override var accuracy: Int = SensorEvents.NO_ACCURACY
        private set

    private val timeIndex: Int
    private val valueIndex = IntArray(stream.valueCount)
    private val accuracyIndex: Int

    init {
        try {
            val header = csv.header(stream.header)
            timeIndex = header.require(SessionStream.TIMESTAMP_COLUMN)
            for (k in valueIndex.indices) valueIndex[k] = header.require(stream.valueColumns[k])
            accuracyIndex = if (stream.hasAccuracy) header.require(SessionStream.ACCURACY_COLUMN) else -1
        } catch (e: Throwable) {
            csv.close()
            throw e
        }
    }

    override fun next(): Boolean {
        if (!csv.nextRecord(skipCutLastLine)) return false
        var field = timeIndex
        try {
            timestampNs = csv.parseLong(field)
            for (k in valueIndex.indices) {
                field = valueIndex[k]
                // Values are 32-bit floats written as their shortest decimal (docs/SESSION_FORMAT.md): taken as that
                // float, the replay sees exactly what the phone's filter saw, not the nearest double of the decimal.
                val d = csv.parseDouble(field, emptyIsNaN = stream == SessionStream.ROTATION_VECTOR && k == 4)
                val f = d.toFloat()
                if (f.isInfinite() && !d.isInfinite()) throw FieldError("$d is outside the 32-bit float range of session values")
                values[k] = f.toDouble()
            }
            if (accuracyIndex >= 0) {
                field = accuracyIndex
                val a = csv.parseLong(field)
                if (a < -1 || a > 3) throw FieldError("accuracy $a is not one of -1, 0, 1, 2, 3")
                accuracy = a.toInt()
            }
        } catch (e: FieldError) {
            throw csv.error(field, "column ${columnName(field)}: ${e.reason}")
        }
        return true
    }

    private fun columnName(field: Int): String = when (field) {
        timeIndex -> SessionStream.TIMESTAMP_COLUMN
        accuracyIndex -> SessionStream.ACCURACY_COLUMN
        else -> stream.valueColumns.getOrElse(valueIndex.indexOf(field)) { "?" }
    }

    override fun close(): Unit = csv.close()
}
