/*
 * Repair of a session whose recording process was killed (docs/SESSION_FORMAT.md, "Recovery"):
 * the writer leaves whole rows up to its last flush, possibly followed by a partial row, and
 * meta.json with "complete": false.
 */
package dev.motionfusion.core.session

import java.io.RandomAccessFile
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path

/** What [SessionRecovery.recover] did: bytes cut from each file, and the new metadata. */
public data class RecoveryReport(val truncatedBytes: Map<SessionStream, Long>, val metadata: SessionMetadata) {
    /** True when a file was changed. */
    public val repaired: Boolean get() = truncatedBytes.values.any { it > 0 }
}

public object SessionRecovery {
    /**
     * True when [dir] holds a session that was never finished (meta.json says "complete": false):
     * its process was killed or its writer abandoned after a failure. False for a complete
     * session, and for a folder whose meta.json is missing or unreadable (not a session).
     */
    @JvmStatic
    public fun isInterrupted(dir: Path): Boolean = try {
        SessionReader.open(dir).use { !it.metadata.complete }
    } catch (e: dev.motionfusion.core.io.DataFormatException) {
        false
    } catch (e: java.io.IOException) {
        false
    }

    /**
     * Repairs the session folder [dir] in place: cuts each CSV after its last complete line (a
     * file cut inside its header gets the header back), recomputes the per-stream statistics,
     * closes an open pause at the end, and rewrites meta.json with "recovered": true and
     * "complete": true. A complete session is left as it is.
     * @throws dev.motionfusion.core.io.DataFormatException when meta.json or a kept row is malformed.
     */
    @JvmStatic
    public fun recover(dir: Path): RecoveryReport {
        val metaFile = dir.resolve(SessionMetadata.FILE_NAME)
        val meta = SessionReader.open(dir).use { it.metadata }
        if (meta.complete) return RecoveryReport(emptyMap(), meta)
        val truncated = LinkedHashMap<SessionStream, Long>()
        for (s in SessionStream.entries) {
            val f = dir.resolve(s.fileName)
            if (!Files.isRegularFile(f)) continue
            truncated[s] = cutAfterLastNewline(f, s)
        }
        val stats = LinkedHashMap<SessionStream, StreamStats>()
        var end = meta.endElapsedRealtimeNs ?: Long.MIN_VALUE
        SessionReader.open(dir).use { r ->
            for (s in r.streams) {
                val acc = StatsAccumulator()
                r.stream(s).use { e -> while (e.next()) acc.add(e.timestampNs) }
                val st = acc.result()
                stats[s] = st
                if (st.samples > 0) end = maxOf(end, st.lastTimestampNs)
            }
        }
        val endNs = if (end == Long.MIN_VALUE) null else end
        val pauses = meta.pauses.map { if (it.endElapsedRealtimeNs == null) it.copy(endElapsedRealtimeNs = endNs ?: it.startElapsedRealtimeNs) else it }
        val reason = meta.endReason.ifEmpty { "interrupted" }
        val repaired = meta.copy(complete = true, recovered = true, endElapsedRealtimeNs = endNs, endReason = reason, streams = stats, pauses = pauses)
        Files.write(metaFile, MetadataJson.write(repaired).toByteArray(StandardCharsets.UTF_8))
        return RecoveryReport(truncated, repaired)
    }

    /** Cuts [f] after its last '\n'; returns the number of bytes removed. */
    private fun cutAfterLastNewline(f: Path, s: SessionStream): Long {
        RandomAccessFile(f.toFile(), "rw").use { raf ->
            val length = raf.length()
            val block = ByteArray(8192)
            var end = length
            while (end > 0) {
                val start = maxOf(0L, end - block.size)
                val n = (end - start).toInt()
                raf.seek(start)
                raf.readFully(block, 0, n)
                for (k in n - 1 downTo 0) {
                    if (block[k] == '\n'.code.toByte()) {
                        val keep = start + k + 1
                        raf.setLength(keep)
                        return length - keep
                    }
                }
                end = start
            }
            // Not even the header line is complete: write it again.
            val header = (s.header + "\n").toByteArray(StandardCharsets.US_ASCII)
            raf.setLength(0)
            raf.write(header)
            return length
        }
    }
}
