/*
 * Repair of a session whose recording process was killed (docs/SESSION_FORMAT.md, "Recovery"):
 * the writer leaves whole rows up to its last flush, possibly followed by a partial row, and
 * meta.json with "complete": false.
 *
 * Recovery must never make things worse, so it
 *  - acts only on a folder whose meta.json carries the format marker ("format":
 *    "motion-fusion-session"), or, when meta.json is missing or unreadable, on a folder that
 *    holds nothing but session files with their exact headers (meta.json is then rebuilt from
 *    the streams and the unreadable one kept as meta.json.unreadable);
 *  - reads and checks every stream before it changes any: a malformed row stops it with
 *    nothing changed;
 *  - never follows a symbolic link and touches only the known files of the folder;
 *  - keeps every meta.json member it does not know;
 *  - changes files in an order that a kill or a full disk at any step leaves recoverable:
 *    cutting a partial last row needs no space and is idempotent, meta.json is replaced
 *    atomically and last (AtomicFiles), so until then the session still reads as interrupted.
 */
package dev.motionfusion.core.session

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.ByteCsvReader
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.FileOperations
import dev.motionfusion.core.io.Json
import java.io.IOException
import java.nio.ByteBuffer
import java.nio.channels.FileChannel
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.LinkOption
import java.nio.file.NoSuchFileException
import java.nio.file.Path
import java.nio.file.StandardOpenOption
import java.nio.file.attribute.BasicFileAttributes

/**
 * What [SessionRecovery.recover] did (or, for a dry run, would do): bytes cut from each file,
 * the new metadata, and the steps in words.
 */
public data class RecoveryReport(
    val truncatedBytes: Map<SessionStream, Long>,
    val metadata: SessionMetadata,
    /** The changes, one line each (e.g. "gyroscope.csv: cut 17 bytes of a partial last row"); empty when none. */
    val actions: List<String> = emptyList(),
    /** True when meta.json was missing or unreadable and is rebuilt from the streams. */
    val rebuiltMetadata: Boolean = false,
    /** True when nothing was changed because a dry run was asked for. */
    val dryRun: Boolean = false,
    /** Bytes cut from markers.csv. */
    val markersTruncatedBytes: Long = 0L,
) {
    /** True when a stream file or markers.csv was (or would be) changed. */
    public val repaired: Boolean get() = truncatedBytes.values.any { it > 0 } || markersTruncatedBytes > 0

    /** True when the session was already complete: nothing to do. */
    public val wasComplete: Boolean get() = actions.isEmpty()
}

/** Recovery of interrupted sessions through [files] (the real file system unless a test passes another). */
public class SessionRecovery(private val files: FileOperations = FileOperations.SYSTEM) {
    private val atomic = AtomicFiles(files)

    /**
     * Repairs the session folder [dir] in place (see the file comment): cuts each CSV after its
     * last complete line (a file cut inside its header gets the header back), recomputes the
     * per-stream statistics, closes an open pause at the end, and replaces meta.json with
     * "recovered": true and "complete": true. A complete session is left as it is. With
     * [dryRun] nothing is changed and the report says what would be.
     * @throws DataFormatException when the folder is not a session of this project, holds a
     *   link where a session file belongs, or a kept row or meta.json is malformed; nothing is
     *   changed then.
     * @throws IOException when a file cannot be read or written (it names the file and reason).
     */
    public fun recover(dir: Path, dryRun: Boolean): RecoveryReport {
        val root = dir.toRealPath()
        if (!Files.isDirectory(root)) throw DataFormatException(dir.toString(), 0, 0, "not a folder: a session is recovered as a folder")
        val entries = list(root)
        for (name in SESSION_FILES) {
            val a = entries[name] ?: continue
            if (a.isSymbolicLink) throw refused(root, name, "is a symbolic link; recovery never follows links")
            if (!a.isRegularFile) throw refused(root, name, "is not a regular file")
        }
        val metaFile = root.resolve(SessionMetadata.FILE_NAME)
        val original = if (entries.containsKey(SessionMetadata.FILE_NAME)) readMeta(metaFile) else null
        val meta: SessionMetadata
        val raw: Map<*, *>?
        if (original != null) {
            meta = original.second
            raw = original.first
            if (meta.complete) return RecoveryReport(emptyMap(), meta, dryRun = dryRun)
        } else {
            checkLooksLikeSession(root, entries)
            meta = SessionMetadata(source = "rebuilt by recovery from the stream files")
            raw = null
        }

        // 1. Check every stream and plan the cuts; nothing is changed before all are read.
        val plans = SessionStream.entries.filter { entries.containsKey(it.fileName) }.map { plan(root, it.fileName, it.header, it) }
        val markerPlan = if (entries.containsKey(SessionMarkers.FILE_NAME)) plan(root, SessionMarkers.FILE_NAME, SessionMarkers.HEADER, null) else null
        val stats = LinkedHashMap<SessionStream, StreamStats>()
        var end = meta.endElapsedRealtimeNs ?: Long.MIN_VALUE
        for (p in plans) {
            stats[p.stream!!] = p.stats
            if (p.stats.samples > 0) end = maxOf(end, p.stats.lastTimestampNs)
        }
        val endNs = if (end == Long.MIN_VALUE) null else end
        val pauses = meta.pauses.map {
            if (it.endElapsedRealtimeNs != null) it else it.copy(endElapsedRealtimeNs = maxOf(it.startElapsedRealtimeNs, endNs ?: it.startElapsedRealtimeNs))
        }
        val repaired = meta.copy(
            complete = true, recovered = true, endElapsedRealtimeNs = endNs,
            endReason = meta.endReason.ifEmpty { "interrupted" }, streams = stats, pauses = pauses,
            markers = markerPlan?.stats,
        )
        val allPlans = plans + listOfNotNull(markerPlan)
        val actions = ArrayList<String>()
        val stale = entries.keys.filter { isTemporary(it) && entries.getValue(it).isRegularFile }.sorted()
        for (name in stale) actions += "$name: remove (left by an interrupted write)"
        for (p in allPlans) {
            when {
                p.restoreHeader -> actions += "${p.fileName}: cut inside its header; write the header again"
                p.cut > 0 && p.linked -> actions += "${p.fileName}: cut ${p.cut} bytes of a partial last row (in a copy: the file has other hard links, which keep it as it was)"
                p.cut > 0 -> actions += "${p.fileName}: cut ${p.cut} bytes of a partial last row"
            }
        }
        val keepUnreadable = raw == null && entries.containsKey(SessionMetadata.FILE_NAME) && !entries.containsKey(UNREADABLE_META)
        if (keepUnreadable) actions += "${SessionMetadata.FILE_NAME}: unreadable; keep it as $UNREADABLE_META"
        actions += if (raw == null) {
            "${SessionMetadata.FILE_NAME}: rebuild from the streams (${stats.values.sumOf { it.samples }} samples), \"complete\": true, \"recovered\": true"
        } else {
            "${SessionMetadata.FILE_NAME}: statistics of ${stats.size} streams, \"complete\": true, \"recovered\": true (other members kept)"
        }
        val report = RecoveryReport(
            plans.associate { it.stream!! to it.cut }, repaired, actions, rebuiltMetadata = raw == null, dryRun = dryRun,
            markersTruncatedBytes = markerPlan?.cut ?: 0L,
        )
        // A session still being written grows while it is read: its counts would be wrong at once.
        requireUnchanged(root, allPlans, "nothing was changed")
        if (dryRun) return report

        // 2. Change: leftovers, partial rows, then meta.json last (atomic), so a kill at any step
        //    leaves a session that reads as interrupted and is recovered again the same way.
        for (name in stale) files.delete(root.resolve(name))
        for (p in allPlans) {
            val f = root.resolve(p.fileName)
            when {
                p.restoreHeader -> atomic.write(f, (p.header + "\n").toByteArray(StandardCharsets.US_ASCII))
                // A file with other hard links is replaced by a cut copy, never cut in place:
                // the other names keep what they held.
                p.cut > 0 && p.linked -> atomic.write(f) { out -> copyPrefix(f, p.keep, out) }
                p.cut > 0 -> AtomicFiles.named(f) { files.truncate(f, p.keep) }
            }
        }
        if (keepUnreadable) atomic.write(root.resolve(UNREADABLE_META), Files.readAllBytes(metaFile))
        requireSizes(root, allPlans.map { if (it.restoreHeader) it.header.length + 1L else it.keep }.zip(allPlans), "partial rows were cut, meta.json is as it was")
        val json = if (raw != null) MetadataJson.writeKeeping(raw, repaired) else MetadataJson.write(repaired)
        atomic.write(metaFile, json.toByteArray(StandardCharsets.UTF_8))
        return report
    }

    /** Fails when a file's size is no longer what it was read at: the session is still being written. */
    private fun requireUnchanged(root: Path, plans: List<Plan>, done: String) =
        requireSizes(root, plans.map { it.keep + it.cut }.zip(plans), done)

    private fun requireSizes(root: Path, sizes: List<Pair<Long, Plan>>, done: String) {
        for ((size, p) in sizes) {
            val f = root.resolve(p.fileName)
            val now = AtomicFiles.named(f) { Files.readAttributes(f, BasicFileAttributes::class.java, LinkOption.NOFOLLOW_LINKS).size() }
            if (now != size) {
                throw DataFormatException(f.toString(), 0, 0, "is still being written: it was $size bytes and is now $now while recovery read it " +
                    "($done); recover the session once its recording has stopped")
            }
        }
    }

    /** A file's check result: its statistics over the complete rows, and where to cut ([stream] null: markers.csv). */
    private class Plan(
        val fileName: String, val header: String, val stream: SessionStream?,
        val keep: Long, val cut: Long, val restoreHeader: Boolean, val stats: StreamStats,
        /** The file has other hard links (it is then never changed in place). */
        val linked: Boolean = false,
    )

    /** Reads the file of stream [s] (or markers.csv) once to its end: every complete row must parse; the cut goes after the last '\n'. */
    private fun plan(root: Path, fileName: String, header: String, s: SessionStream?): Plan {
        val f = root.resolve(fileName)
        val length: Long
        val keep: Long
        FileChannel.open(f, StandardOpenOption.READ, LinkOption.NOFOLLOW_LINKS).use { ch ->
            length = ch.size()
            keep = lastNewlineEnd(ch, length)
        }
        if (keep == 0L) {
            // Cut inside the header line: only a prefix of the header is expected there.
            val head = String(Files.readAllBytes(f), StandardCharsets.US_ASCII)
            if (!header.startsWith(head)) throw refused(root, fileName, "holds no header line and is not a cut-off '$header'")
            return Plan(fileName, header, s, 0L, length, restoreHeader = true, StatsAccumulator().result())
        }
        val acc = StatsAccumulator()
        // Only the rows kept: what a writer appends meanwhile is not counted (and is caught by requireUnchanged).
        val csv = ByteCsvReader(Prefix(Files.newInputStream(f, StandardOpenOption.READ, LinkOption.NOFOLLOW_LINKS), keep), f.toString())
        if (s != null) {
            SessionCsvCursor(s, csv, skipCutLastLine = true).use { c -> while (c.next()) acc.add(c.timestampNs) }
        } else {
            MarkerCursor(csv, skipCutLastLine = true).use { c -> while (c.next()) acc.add(c.timestampNs) }
        }
        return Plan(fileName, header, s, keep, length - keep, restoreHeader = false, acc.result(), linked = linkCount(f) > 1)
    }

    /** The first [left] bytes of [input]. */
    private class Prefix(private val input: java.io.InputStream, private var left: Long) : java.io.InputStream() {
        override fun read(): Int = if (left <= 0L) -1 else input.read().also { if (it >= 0) left-- }

        override fun read(b: ByteArray, off: Int, len: Int): Int {
            if (len == 0) return 0
            if (left <= 0L) return -1
            val n = input.read(b, off, minOf(len.toLong(), left).toInt())
            if (n > 0) left -= n
            return n
        }

        override fun close() = input.close()
    }

    /** The number of names (hard links) of [f]; 1 where the file system does not say. */
    private fun linkCount(f: Path): Int = try {
        (Files.getAttribute(f, "unix:nlink", LinkOption.NOFOLLOW_LINKS) as Number).toInt()
    } catch (e: UnsupportedOperationException) {
        1
    } catch (e: IllegalArgumentException) {
        1
    }

    /** Copies the first [bytes] bytes of [f] to [out]. */
    private fun copyPrefix(f: Path, bytes: Long, out: java.io.OutputStream) {
        Files.newInputStream(f, StandardOpenOption.READ, LinkOption.NOFOLLOW_LINKS).use { input ->
            val buf = ByteArray(1 shl 16)
            var left = bytes
            while (left > 0) {
                val n = input.read(buf, 0, minOf(left, buf.size.toLong()).toInt())
                if (n < 0) throw IOException("$f: shorter than when it was read")
                out.write(buf, 0, n)
                left -= n
            }
        }
    }

    /** Byte offset just after the last '\n' of the file (0 when it has none). */
    private fun lastNewlineEnd(ch: FileChannel, length: Long): Long {
        val block = ByteArray(8192)
        var end = length
        while (end > 0) {
            val start = maxOf(0L, end - block.size)
            val buf = ByteBuffer.wrap(block, 0, (end - start).toInt())
            var at = start
            while (buf.hasRemaining()) {
                val n = ch.read(buf, at)
                if (n < 0) break
                at += n
            }
            for (k in (at - start).toInt() - 1 downTo 0) if (block[k] == NEWLINE) return start + k + 1
            end = start
        }
        return 0L
    }

    /** meta.json as (raw JSON object, metadata), or null when it is unreadable (rebuilt then). */
    private fun readMeta(metaFile: Path): Pair<Map<*, *>, SessionMetadata>? {
        val bytes = Files.newInputStream(metaFile, StandardOpenOption.READ, LinkOption.NOFOLLOW_LINKS).use { it.readBytes() }
        val text = String(bytes, StandardCharsets.UTF_8)
        val json = try {
            Json.parse(text, metaFile.toString())
        } catch (e: DataFormatException) {
            // Rebuilt only when cut short (a full disk during an old in-place write, a lost
            // write): any other fault, such as nesting deeper than the reader's limit, may be a
            // complete session that another program changed, and is left as it is.
            if (Json.endsEarly(text)) return null
            throw DataFormatException(e.source, e.line, e.column, "${e.reason}: not a meta.json cut short, so not rebuilt; left untouched", e)
        }
        val root = json as? Map<*, *>
        if (root == null || root["format"] != MetadataJson.FORMAT_MARKER) {
            throw DataFormatException(
                metaFile.toString(), 0, 0,
                "not a Motion Fusion session (no \"format\": \"${MetadataJson.FORMAT_MARKER}\"); left untouched",
            )
        }
        return root to MetadataJson.parse(text, metaFile.toString())
    }

    /**
     * Without a readable meta.json, the folder is taken for an interrupted session only when it
     * holds session files and nothing else, each stream file starting with its exact header.
     */
    private fun checkLooksLikeSession(root: Path, entries: Map<String, BasicFileAttributes>) {
        val foreign = entries.keys.filter { it !in SESSION_FILES && it != UNREADABLE_META && !isTemporary(it) }
        val streams = SessionStream.entries.filter { entries.containsKey(it.fileName) }
        if (streams.isEmpty() || foreign.isNotEmpty()) {
            val what = if (streams.isEmpty()) "no stream file" else "other files (${foreign.sorted().take(3).joinToString()})"
            throw DataFormatException(
                root.resolve(SessionMetadata.FILE_NAME).toString(), 0, 0,
                "missing or unreadable, and the folder holds $what: not taken for a session; left untouched",
            )
        }
        val withHeaders = streams.map { it.fileName to it.header } +
            (if (entries.containsKey(SessionMarkers.FILE_NAME)) listOf(SessionMarkers.FILE_NAME to SessionMarkers.HEADER) else emptyList())
        for ((fileName, header) in withHeaders) {
            val f = root.resolve(fileName)
            val head = Files.newInputStream(f, StandardOpenOption.READ, LinkOption.NOFOLLOW_LINKS).use { input ->
                val b = ByteArray(header.length + 1)
                var n = 0
                while (n < b.size) {
                    val r = input.read(b, n, b.size - n)
                    if (r < 0) break
                    n += r
                }
                String(b, 0, n, StandardCharsets.US_ASCII)
            }
            val line = head.substringBefore('\n')
            if (if ('\n' in head) line != header else !header.startsWith(head)) {
                throw refused(root, fileName, "does not start with the header '$header': not taken for a session; left untouched")
            }
        }
    }

    public companion object {
        /** Where recovery keeps an unreadable meta.json it rebuilt. */
        internal const val UNREADABLE_META: String = "meta.json.unreadable"

        private const val NEWLINE = '\n'.code.toByte()
        /**
         * The files of a session: meta.json, the stream files, markers.csv, clock.csv (recovery touches no other, and
         * leaves clock.csv as it is: its reader skips a cut last line; the zip holds no other).
         */
        internal val SESSION_FILES: List<String> = listOf(SessionMetadata.FILE_NAME) + SessionStream.entries.map { it.fileName } + SessionMarkers.FILE_NAME + SessionClock.FILE_NAME

        /**
         * True when [dir] holds a session that was never finished: meta.json says
         * "complete": false (its process was killed or its writer abandoned after a failure), or
         * meta.json is missing or unreadable in a folder that holds nothing but session files.
         * False for a complete session and for anything recovery would refuse.
         */
        @JvmStatic
        public fun isInterrupted(dir: Path): Boolean = try {
            !SessionRecovery().recover(dir, dryRun = true).wasComplete
        } catch (e: DataFormatException) {
            false
        } catch (e: IOException) {
            false
        }

        /** [SessionRecovery.recover] on the real file system, changing the folder. */
        @JvmStatic
        public fun recover(dir: Path): RecoveryReport = SessionRecovery().recover(dir, dryRun = false)

        /** A temporary file of an interrupted write aside of a session file (meta.json, or a cut copy of a stream). */
        private fun isTemporary(name: String) = SESSION_FILES.any { AtomicFiles.isTemporaryOf(name, it) }

        private fun refused(root: Path, name: String, reason: String) = DataFormatException(root.resolve(name).toString(), 0, 0, "$reason; nothing changed")

        /** The folder's entries by name, links not followed. */
        private fun list(root: Path): Map<String, BasicFileAttributes> {
            val out = HashMap<String, BasicFileAttributes>()
            Files.newDirectoryStream(root).use { ds ->
                for (p in ds) {
                    val a = try {
                        Files.readAttributes(p, BasicFileAttributes::class.java, LinkOption.NOFOLLOW_LINKS)
                    } catch (e: NoSuchFileException) {
                        continue
                    }
                    out[p.fileName.toString()] = a
                }
            }
            return out
        }
    }
}
