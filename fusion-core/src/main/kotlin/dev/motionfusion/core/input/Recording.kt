/*
 * Any input `fusion` replays, opened by path and recognised by content: a session (folder or
 * zip), a plain IMU table (.csv or .csv.gz, or a trial folder holding input.csv[.gz]), a
 * phyphox export (zip, folder or single CSV), a Sensor Logger export (zip or folder), the IMU of
 * an EuRoC (ASL) folder or a Kalibr imu0.csv. One input is one recording: a folder holding
 * several is an error that lists them.
 */
package dev.motionfusion.core.input

import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FileSet
import dev.motionfusion.core.io.InputLimits
import dev.motionfusion.core.io.Inputs
import dev.motionfusion.core.event.MergedEvents
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.session.Marker
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
import java.io.Closeable
import java.nio.file.NoSuchFileException
import java.nio.file.Path

/** The kinds of input `fusion` understands. */
public enum class RecordingFormat(public val description: String) {
    SESSION("Motion Fusion session"),
    IMU_TABLE("plain IMU table"),
    PHYPHOX("phyphox export"),
    SENSOR_LOGGER("Sensor Logger export"),
    EUROC("EuRoC (ASL) IMU data"),
    KALIBR("Kalibr imu0.csv"),
}

/**
 * How inputs are read: [limits] on decompressed bytes, and the [platform] of a Sensor Logger
 * export where its Metadata.csv does not say (null: infer, else assume Android).
 */
public data class ImportOptions(val limits: InputLimits = InputLimits(), val platform: Platform? = null)

/**
 * An opened input. [events] may be called more than once (each call reads from the start).
 *
 * @property originNs the timestamp that is t = 0 s in outputs: the session's start anchor, 0 for
 *   tables and phyphox (their times are already relative), null for "the first event".
 * @property metadata the session's meta.json; null for other formats.
 * @property notes what the import assumed or left out (print them as warnings).
 */
public class Recording private constructor(
    public val name: String,
    public val format: RecordingFormat,
    public val metadata: SessionMetadata?,
    public val originNs: Long?,
    /** The streams this input provides. */
    public val streams: Set<SessionStream>,
    public val notes: List<String>,
    private val files: FileSet,
    private val open: () -> SensorEvents,
    private val closer: Closeable,
    private val readMarkers: () -> List<Marker> = { emptyList() },
    private val readClock: () -> List<dev.motionfusion.core.sync.ClockExchange> = { emptyList() },
) : Closeable {
    /**
     * Whether the input has magnetometer readings: the stream is present and a session's meta.json does not count
     * 0 samples of it (a file that holds its header alone). Without them a filter runs in 6D.
     */
    public val hasMagnetometer: Boolean
        get() = SessionStream.MAGNETOMETER in streams && metadata?.streams?.get(SessionStream.MAGNETOMETER)?.samples != 0L

    /** The streams whose plausibility probe has passed (it runs once per stream, before its first events). */
    private val probed = HashSet<SessionStream>()

    /** The markers set while recording (a session's markers.csv); empty for other formats. */
    public fun markers(): List<Marker> = readMarkers()

    /** The clock exchanges with a laptop (a session's clock.csv, on the laptop clock its meta.json names); empty otherwise. */
    public fun clockExchanges(): List<dev.motionfusion.core.sync.ClockExchange> = readClock()

    /**
     * The events of [which] streams (default all), merged by timestamp. Only those streams are probed for
     * plausibility: a replay without the magnetometer (6D) is not refused for a magnetometer that read nothing.
     */
    public fun events(which: Set<SessionStream> = streams): SensorEvents {
        val need = streams.filterTo(HashSet()) { it in which && it !in probed }
        if (need.isNotEmpty()) {
            files.guard.reset()
            Plausibility.check(name, format, need, open())
            probed += need
        }
        files.guard.reset()
        val all = open()
        return if (which.containsAll(streams)) all else FilteredEvents(all, which)
    }

    override fun close(): Unit = closer.close()

    public companion object {
        /** With a second core, a plain table is parsed ahead while the previous rows are filtered. */
        private val PARSE_AHEAD = Runtime.getRuntime().availableProcessors() > 1

        /**
         * Opens [path], recognising its format by content.
         * @throws DataFormatException when it is none of the formats, holds several recordings, or is malformed.
         * @throws NoSuchFileException when it does not exist.
         */
        @JvmStatic
        @JvmOverloads
        public fun open(path: Path, options: ImportOptions = ImportOptions()): Recording {
            val files = FileSet.open(path, options.limits)
            try {
                return open(files, path, options)
            } catch (e: DataFormatException) {
                files.close()
                // What is missing may be what a link out of the folder held.
                if (files.linksOut.isEmpty()) throw e
                throw DataFormatException(e.source, e.line, e.column, "${e.reason} (${linksOut(files)})", e)
            } catch (e: Throwable) {
                files.close()
                throw e
            }
        }

        /** The links out of the folder of [files], said once. */
        private fun linksOut(files: FileSet): String {
            val l = files.linksOut.sorted()
            val shown = l.take(5).joinToString(", ") + if (l.size > 5) ", …" else ""
            val (are, them) = if (l.size == 1) "is a link" to "it" else "are links" to "them"
            return "$shown $are out of the folder, not followed: copy $them in to have $them read"
        }

        private fun open(files: FileSet, path: Path, options: ImportOptions): Recording {
            val (dir, kind) = locate(files)
            val own = if (Inputs.isStandardInput(path)) files.name else (path.fileName ?: path).toString()
            val folders = dir.removeSuffix("/").split('/').filter { it.isNotEmpty() }
            // An EuRoC recording is named after the folder that holds its mav0/.
            val named = if (kind == RecordingFormat.EUROC && folders.lastOrNull().equals("mav0", ignoreCase = true)) folders.dropLast(1) else folders
            val name = named.lastOrNull() ?: own
            val linkNotes = if (files.linksOut.isEmpty()) emptyList() else listOf(linksOut(files))
            return when (kind) {
                RecordingFormat.SESSION -> {
                    val r = SessionReader.open(files, dir)
                    Recording(name, kind, r.metadata, r.metadata.startAnchor?.elapsedRealtimeNs, r.streams, linkNotes, files, { r.events() }, r, r::markers, r::clockExchanges)
                }
                RecordingFormat.IMU_TABLE -> {
                    val table = files.find(dir, "input.csv.gz") ?: files.find(dir, "input.csv") ?: files.filesIn(dir).first { isTable(files, it) }
                    val hasMag = ImuTableReader(files.csv(table)).use { it.hasMagnetometer }
                    val streams = setOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE) + (if (hasMag) setOf(SessionStream.MAGNETOMETER) else emptySet())
                    Recording(name, kind, null, 0L, streams, linkNotes, files, { ImuTableEvents(ImuTableReader(files.csv(table)), ahead = PARSE_AHEAD) }, files)
                }
                RecordingFormat.PHYPHOX, RecordingFormat.SENSOR_LOGGER -> {
                    val plan = if (kind == RecordingFormat.PHYPHOX) PhyphoxImport.plan(files, dir) else SensorLoggerImport.plan(files, dir, options.platform)
                    val origin = if (kind == RecordingFormat.PHYPHOX) 0L else null
                    Recording(name, kind, null, origin, plan.streams, linkNotes + plan.notes, files, { openAll(files, plan) }, files)
                }
                RecordingFormat.EUROC, RecordingFormat.KALIBR -> {
                    // Times of their own clock (EuRoC's are ns since the epoch): t = 0 s is the first event.
                    val plan = VioDatasetImport.plan(files, dir, kind)
                    Recording(name, kind, null, null, plan.streams, linkNotes + plan.notes, files, { openAll(files, plan) }, files)
                }
            }
        }

        private fun openAll(files: FileSet, plan: ImportPlan): SensorEvents {
            val cursors = ArrayList<dev.motionfusion.core.event.StreamCursor>()
            try {
                for (s in plan.sources) cursors += s.open(files)
            } catch (e: Throwable) {
                cursors.forEach { runCatching { it.close() } }
                throw e
            }
            return MergedEvents(cursors)
        }

        private fun isTable(files: FileSet, path: String): Boolean =
            isText(path) && files.firstLine(path)?.let { ImuTableReader.recognises(it) } == true

        private fun isText(path: String) = path.endsWith(".csv", true) || path.endsWith(".csv.gz", true) || path.endsWith(".txt", true) || '.' !in path.substringAfterLast('/')

        /**
         * The one recording in [files]: its folder ("" or ending in '/') and format. Several
         * candidate folders (or zips inside a folder) are an error listing them.
         */
        private fun locate(files: FileSet): Pair<String, RecordingFormat> {
            val found = LinkedHashMap<String, RecordingFormat>()
            val zips = ArrayList<String>()
            fun dirOf(p: String) = p.substring(0, p.lastIndexOf('/') + 1)
            // An EuRoC folder (…/imu0/data.csv with EuRoC's header): its subfolders belong to it.
            val euroc = ArrayList<String>()
            for (p in files.paths) {
                if (!p.endsWith("imu0/data.csv", true) || !(p.length == 13 || p[p.length - 14] == '/')) continue
                if (files.firstLine(p)?.let(VioDatasetImport::recognisesEuroc) != true) continue
                val root = dirOf(dirOf(p).removeSuffix("/"))
                found[root] = RecordingFormat.EUROC
                euroc += root
            }
            // Files that name their folder's format (a trial's input table wins over its meta.json) ...
            for (p in files.paths) {
                val base = p.substring(p.lastIndexOf('/') + 1)
                if (euroc.any { p.startsWith(it) }) continue
                when {
                    base.equals("input.csv", true) || base.equals("input.csv.gz", true) -> found[dirOf(p)] = RecordingFormat.IMU_TABLE
                    base.equals(SessionMetadata.FILE_NAME, true) -> found.putIfAbsent(dirOf(p), RecordingFormat.SESSION)
                    files.isFolder && base.endsWith(".zip", true) -> zips += p
                }
            }
            // ... then, in the other folders, the headers of the CSVs.
            val named = found.keys.toSet()
            // Plain IMU tables by folder: each is a recording of its own, so two in one folder are two.
            val tables = LinkedHashMap<String, MutableList<String>>()
            for (p in files.paths) {
                val dir = dirOf(p)
                if (dir in named || !isText(p) || euroc.any { p.startsWith(it) }) continue
                val header = files.firstLine(p) ?: continue
                val known = found[dir]
                when {
                    VioDatasetImport.recognisesEuroc(header) -> found[dir] = RecordingFormat.EUROC
                    VioDatasetImport.recognisesKalibr(header) -> found[dir] = RecordingFormat.KALIBR
                    SensorLoggerImport.recognises(header) -> found[dir] = RecordingFormat.SENSOR_LOGGER
                    known == RecordingFormat.SENSOR_LOGGER -> Unit
                    PhyphoxImport.recognises(header, p) -> found[dir] = RecordingFormat.PHYPHOX
                    (known == null || known == RecordingFormat.IMU_TABLE) && ImuTableReader.recognises(header) -> {
                        found[dir] = RecordingFormat.IMU_TABLE
                        tables.getOrPut(dir) { ArrayList() } += p
                    }
                }
            }
            val candidates = found.entries.flatMap { (dir, kind) ->
                val own = tables[dir]
                // Named by their files where the folder cannot tell them apart (several, or the top folder itself).
                if (kind == RecordingFormat.IMU_TABLE && own != null && (own.size > 1 || dir.isEmpty())) own else listOf(dir.ifEmpty { "." })
            } + zips
            if (candidates.size > 1) {
                val shown = candidates.take(12).joinToString(", ") { it.removeSuffix("/") } + if (candidates.size > 12) ", …" else ""
                throw DataFormatException(files.name, 0, 0, "holds ${candidates.size} recordings ($shown): name the one to read")
            }
            val only = found.entries.singleOrNull()
            if (only != null) return only.key to only.value
            if (zips.size == 1) throw DataFormatException(files.name, 0, 0, "holds no recording of its own but the zip ${zips[0]}: name it")
            val first = files.paths.firstOrNull()?.let { files.firstLine(it) }
            val detail = if (files.paths.size == 1 && first != null) " (first line '${ByteCsvReader.escapedExcerpt(first)}')" else ""
            throw DataFormatException(files.name, if (detail.isEmpty()) 0 else 1, 0,
                "not a recognised input$detail: expected a session (folder or zip with meta.json), an IMU table (t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]), " +
                    "a phyphox export, a Sensor Logger export, an EuRoC (ASL) folder or a Kalibr imu0.csv")
        }
    }
}

/** Passes only the events of [which]. */
private class FilteredEvents(private val inner: SensorEvents, private val which: Set<SessionStream>) : SensorEvents by inner {
    override fun next(): Boolean {
        while (inner.next()) if (inner.stream in which) return true
        return false
    }
}
