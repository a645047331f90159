package dev.motionfusion.app.record

import dev.motionfusion.core.event.SessionStream
import java.io.File
import java.io.IOException
import java.io.OutputStream
import java.io.RandomAccessFile

/**
 * A test double of the session format, just enough for service tests: one text line per row
 * in `rows.txt`, a `finished` marker, recovery that cuts a partial last line and leaves a
 * `recovered` marker. [failAfterBytes] makes the file fail like a full disk.
 */
internal class LineFormat(private val failAfterBytes: Long = Long.MAX_VALUE) : SessionFormat {
    @Volatile var created: File? = null
    /** The metadata of the last session created. */
    @Volatile var metadata: dev.motionfusion.core.session.SessionMetadata? = null

    override fun create(dir: File, metadata: dev.motionfusion.core.session.SessionMetadata): SessionSink {
        created = dir
        this.metadata = metadata
        File(dir, "meta.txt").writeText("sensors=${metadata.sensors.joinToString(",") { it.stream.key }}\n")
        return LineSink(dir, failAfterBytes)
    }

    /** The last row's timestamp (the second field). */
    override fun endNs(dir: File): Long? = rows(dir).lastOrNull()?.split(',')?.get(1)?.toLong()

    override fun isInterrupted(dir: File) = !File(dir, "finished").exists() && !File(dir, "recovered").exists()

    override fun recover(dir: File) {
        val f = File(dir, "rows.txt")
        RandomAccessFile(f, "rw").use { raf ->
            var end = raf.length()
            while (end > 0) {
                raf.seek(end - 1)
                if (raf.read() == '\n'.code) break
                end--
            }
            raf.setLength(end)
        }
        File(dir, "recovered").writeText("")
    }

    companion object {
        fun rows(dir: File): List<String> = File(dir, "rows.txt").readLines().filter { it.isNotEmpty() }
    }
}

/** Bytes pass through until [limit], then every write throws "No space left on device". */
internal class FailingStream(private val out: OutputStream, private val limit: Long) : OutputStream() {
    var written = 0L
        private set

    override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)

    override fun write(b: ByteArray, off: Int, len: Int) {
        val n = minOf((limit - written).coerceAtLeast(0), len.toLong()).toInt()
        if (n > 0) out.write(b, off, n)
        written += n
        if (n < len) {
            out.flush()
            throw IOException("No space left on device")
        }
    }

    override fun flush() = out.flush()
    override fun close() = out.close()
}

internal class LineSink(private val dir: File, failAfterBytes: Long) : SessionSink {
    private val file = java.io.FileOutputStream(File(dir, "rows.txt"))
    private val out = java.io.BufferedOutputStream(FailingStream(file, failAfterBytes), 8192)
    private val sb = StringBuilder()

    override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
        sb.setLength(0)
        sb.append(stream.name).append(',').append(timestampNs).append(',').append(accuracy)
        for (i in 0 until stream.valueCount) sb.append(',').append(values[offset + i])
        sb.append('\n')
        out.write(sb.toString().toByteArray())
    }

    override fun diagnostics(t: Long, bx: Double, by: Double, bz: Double, rest: Boolean, mag: Boolean, acc: Boolean) = Unit

    override fun fused(timestampNs: Long, q: DoubleArray, offset: Int) {
        out.write("FUSED,$timestampNs,${q[offset]},${q[offset + 1]},${q[offset + 2]},${q[offset + 3]}\n".toByteArray())
    }

    override fun marker(timestampNs: Long, label: String) {
        out.write("MARKER,$timestampNs,$label\n".toByteArray())
    }

    override fun checkpoint(anchor: dev.motionfusion.core.session.ClockAnchor) = out.flush()

    override fun flush() = out.flush()

    override fun finish(end: RecordingEnd) {
        out.close()
        File(dir, "finished").writeText(end.toString())
    }

    override fun abandon(end: RecordingEnd) {
        try {
            file.close()
        } catch (_: IOException) {
        }
    }
}
