/*
 * Any input `fusion` replays, opened by path and recognised by content: a session (folder or
 * zip), a plain IMU table (.csv or .csv.gz, or a trial folder holding input.csv[.gz]), a
 * phyphox export (zip, folder or single CSV), a Sensor Logger export (zip or folder).
 */
package dev.motionfusion.core.recording

import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.ImuTableReader
import dev.motionfusion.core.io.Inputs
import dev.motionfusion.core.session.MergedEvents
import dev.motionfusion.core.session.SessionEvents
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.SessionStream
import dev.motionfusion.core.session.StreamCursor
import java.io.Closeable
import java.nio.file.Files
import java.nio.file.NoSuchFileException
import java.nio.file.Path
import java.nio.file.Paths

/** The kinds of input `fusion` understands. */
public enum class RecordingFormat(public val description: String) {
    SESSION("Motion Fusion session"),
    IMU_TABLE("plain IMU table"),
    PHYPHOX("phyphox export"),
    SENSOR_LOGGER("Sensor Logger export"),
}

/**
 * An opened input. [events] may be called more than once (each call reads from the start).
 *
 * @property originNs the timestamp that is t = 0 s in outputs: the session's start anchor, 0 for
 *   tables and phyphox (their times are already relative), null for "the first event".
 * @property metadata the session's meta.json; null for other formats.
 */
public class Recording internal constructor(
    public val name: String,
    public val format: RecordingFormat,
    public val metadata: SessionMetadata?,
    public val originNs: Long?,
    private val open: () -> SessionEvents,
    /** The streams this input provides. */
    public val streams: Set<SessionStream>,
    private val closer: Closeable,
) : Closeable {
    /**
     * The events of [which] streams (default all), merged by timestamp. Broken compressed data
     * (zip, gzip) surfaces as DataFormatException like any other malformed input.
     */
    public fun events(which: Set<SessionStream> = streams): SessionEvents {
        val all = guarded(name) { open() }
        return CompressionGuard(if (which.containsAll(streams)) all else FilteredEvents(all, which), name)
    }

    override fun close(): Unit = closer.close()

    public companion object {
        /**
         * Opens [path], recognising its format by content.
         * @throws DataFormatException when it is none of the formats or is malformed.
         * @throws NoSuchFileException when it does not exist.
         */
        @JvmStatic
        public fun open(path: Path): Recording = guarded(path.toString()) { openUnguarded(path) }

        private fun openUnguarded(path: Path): Recording {
            if (!Files.exists(path)) throw NoSuchFileException(path.toString())
            if (Files.isDirectory(path)) {
                // A trial folder (BROAD layout) may hold a meta.json of its own: input.csv decides first.
                for (n in listOf("input.csv.gz", "input.csv")) {
                    if (Files.isRegularFile(path.resolve(n))) return table(path.resolve(n), path.fileName?.toString() ?: path.toString())
                }
                if (Files.isRegularFile(path.resolve(SessionMetadata.FILE_NAME))) return session(path)
                return export(path)
            }
            if (isZip(path)) {
                val files = InputFiles.open(path)
                val hasMeta = files.find(SessionMetadata.FILE_NAME) != null
                files.close()
                return if (hasMeta) session(path) else export(path)
            }
            val header = Files.newInputStream(path).use { s -> Inputs.reader(s).readLine()?.removePrefix("\uFEFF") }
                ?: throw DataFormatException(path.toString(), 1, 0, "empty file")
            if (PhyphoxImport.recognises(header)) return export(path.parent ?: Paths.get("."), only = path)
            if (header.split(',').any { it.trim().removeSurrounding("\"") == "t_s" }) return table(path)
            throw DataFormatException(path.toString(), 1, 1,
                "not a recognised input: expected a session (folder or zip with meta.json), an IMU table (t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]), " +
                    "a phyphox export or a Sensor Logger export")
        }

        private fun isZip(path: Path): Boolean = Files.newInputStream(path).use { s ->
            val b = ByteArray(4)
            var n = 0
            while (n < 4) n += s.read(b, n, 4 - n).takeIf { it > 0 } ?: break
            n == 4 && b[0] == 'P'.code.toByte() && b[1] == 'K'.code.toByte() && b[2].toInt() == 3 && b[3].toInt() == 4
        }

        private fun session(path: Path): Recording {
            val r = SessionReader.open(path)
            return Recording(r.name, RecordingFormat.SESSION, r.metadata, r.metadata.startAnchor?.elapsedRealtimeNs, { r.events() }, r.streams, r)
        }

        private fun table(path: Path, name: String = path.fileName.toString()): Recording {
            val hasMag = ImuTableReader.open(path).use { it.hasMagnetometer }
            val streams = setOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE) + (if (hasMag) setOf(SessionStream.MAGNETOMETER) else emptySet())
            return Recording(name, RecordingFormat.IMU_TABLE, null, 0L, { ImuTableEvents(ImuTableReader.open(path), path.toString()) }, streams, Closeable { })
        }

        private fun export(path: Path, only: Path? = null): Recording {
            val files = if (only != null) SingleFile(only) else InputFiles.open(path)
            try {
                val format: RecordingFormat
                val make: () -> List<StreamCursor>
                if (only == null && SensorLoggerImport.recognises(files)) {
                    format = RecordingFormat.SENSOR_LOGGER
                    make = { SensorLoggerImport.cursors(files) }
                } else {
                    format = RecordingFormat.PHYPHOX
                    make = { PhyphoxImport.cursors(files) }
                }
                val probe = make()
                val streams = probe.map { it.stream }.toSet()
                probe.forEach { it.close() }
                val origin = if (format == RecordingFormat.PHYPHOX) 0L else null
                return Recording((only ?: path).fileName?.toString() ?: path.toString(), format, null, origin, { MergedEvents(make()) }, streams, files)
            } catch (e: Throwable) {
                files.close()
                if (e is DataFormatException && only == null && e.source == files.name) {
                    throw DataFormatException(path.toString(), 0, 0, "not a recognised input (${e.reason}); expected a session, an IMU table, a phyphox or a Sensor Logger export")
                }
                throw e
            }
        }
    }
}

/** Runs [block], turning corrupt compressed data into [DataFormatException] naming [source]. */
internal inline fun <T> guarded(source: String, block: () -> T): T = try {
    block()
} catch (e: java.util.zip.ZipException) {
    throw DataFormatException(source, 0, 0, "corrupt compressed data: ${e.message}", e)
} catch (e: java.io.EOFException) {
    throw DataFormatException(source, 0, 0, "compressed data ends early: ${e.message}", e)
}

/** [SessionEvents] whose compression errors become [DataFormatException]. */
private class CompressionGuard(private val inner: SessionEvents, private val source: String) : SessionEvents by inner {
    override fun next(): Boolean = guarded(source) { inner.next() }
}

/** A single CSV file seen as a one-file export. */
private class SingleFile(private val file: Path) : InputFiles() {
    override val name: String = file.fileName.toString()
    override val paths: List<String> = listOf(name)
    override fun open(path: String) = Files.newInputStream(file)
    override fun displayName(path: String) = file.toString()
    override fun close() {}
}

/** Passes only the events of [which]. */
private class FilteredEvents(private val inner: SessionEvents, private val which: Set<SessionStream>) : SessionEvents by inner {
    override fun next(): Boolean {
        while (inner.next()) if (inner.stream in which) return true
        return false
    }
}
