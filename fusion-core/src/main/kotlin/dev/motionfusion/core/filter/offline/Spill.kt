/*
 * The offline estimate's temporary file: fixed-size records written forward, read backward and forward.
 */
package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.TemporaryFiles
import java.io.Closeable
import java.io.IOException
import java.nio.Buffer
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.nio.channels.FileChannel
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.StandardOpenOption

/**
 * Fixed-size binary records in a temporary file, written in order and then read backward (each
 * block written back after it) and forward, a block at a time: memory is two blocks whatever the
 * length. The file is unlinked as soon as it is open where the system allows it (then nothing is
 * left behind even if the process is killed); elsewhere it is removed by [close], at exit, and by
 * a shutdown hook on an interrupt.
 *
 * A record, 184 bytes: flags (kind, and for a reference its stream and value count), timestamp ns,
 * then for a step t_s, gyroscope (3), accelerometer (3), magnetometer (3), orientation (4: the first
 * pass's, then the backward pass's), how recently the backward pass met a disturbed field and the
 * heading smoother's filtered state (x, b, the covariance's three terms, u); for a reference up to
 * [MAX_VALUES] values.
 */
internal class Spill(dir: Path?) : Closeable {
    private val path: Path = if (dir == null) Files.createTempFile("fusion-offline-", ".tmp") else Files.createTempFile(dir, ".fusion-offline-", ".tmp")
    val channel: FileChannel
    val block: ByteBuffer = ByteBuffer.allocateDirect(RECORD * BLOCK).order(ByteOrder.nativeOrder())

    /** The same buffer as a java.nio.Buffer (Android 8 has no ByteBuffer overrides of flip, clear, position, limit). */
    val buffer: Buffer = block
    private var unlinked = false
    private var closed = false

    /** Records written. */
    var records = 0L
        private set
    var firstStepNs = Long.MIN_VALUE
        private set
    var lastStepNs = Long.MIN_VALUE
        private set

    init {
        try {
            channel = FileChannel.open(path, StandardOpenOption.READ, StandardOpenOption.WRITE)
        } catch (e: Throwable) {
            Files.deleteIfExists(path)
            throw e
        }
        unlinked = try {
            Files.delete(path)
            true
        } catch (e: IOException) {
            false
        }
        if (!unlinked) {
            path.toFile().deleteOnExit()
            TemporaryFiles.add(path)
        }
    }

    /** Runs [block]; a failure to write the spill names its folder (the file itself may be unlinked) and the reason. */
    inline fun <T> named(block: () -> T): T = try {
        block()
    } catch (e: IOException) {
        throw java.nio.file.FileSystemException(
            folder, null,
            "the offline estimate's temporary file (java.io.tmpdir; give it room, or another folder with -Djava.io.tmpdir=DIR): ${AtomicFiles.reason(e)}",
        ).apply { initCause(e) }
    }

    /** The folder of the spill, for messages. */
    val folder: String = path.toAbsolutePath().parent.toString()

    private fun room() {
        if (block.position() == block.capacity()) {
            buffer.flip()
            named { while (block.hasRemaining()) channel.write(block) }
            buffer.clear()
        }
    }

    fun putStep(flags: Long, t: Long, timeS: Double, g: DoubleArray, a: DoubleArray, m: DoubleArray, q: DoubleArray) {
        room()
        val at = block.position()
        block.putLong(at, flags).putLong(at + 8, t).putDouble(at + TIME, timeS)
        for (k in 0 until 3) {
            block.putDouble(at + GYRO + 8 * k, g[k]).putDouble(at + ACC + 8 * k, a[k]).putDouble(at + MAG + 8 * k, m[k])
        }
        for (k in 0 until 4) block.putDouble(at + Q + 8 * k, q[k])
        buffer.position(at + RECORD)
        records++
        if (firstStepNs == Long.MIN_VALUE) firstStepNs = t
        lastStepNs = t
    }

    fun putReference(stream: Int, t: Long, values: DoubleArray, count: Int) {
        room()
        val at = block.position()
        block.putLong(at, OfflinePasses.REFERENCE or (stream.toLong() shl 8) or (count.toLong() shl 16)).putLong(at + 8, t)
        for (k in 0 until count) block.putDouble(at + VALUES + 8 * k, values[k])
        buffer.position(at + RECORD)
        records++
    }

    fun endWriting() {
        buffer.flip()
        named { while (block.hasRemaining()) channel.write(block) }
        buffer.clear()
    }

    /** [visit] (block, offset of the record) for every record from the last to the first; changes are written back. */
    inline fun backward(visit: (ByteBuffer, Int) -> Unit) {
        var end = records
        while (end > 0) {
            val start = maxOf(0L, end - BLOCK)
            val n = (end - start).toInt()
            read(start, n)
            for (i in n - 1 downTo 0) visit(block, i * RECORD)
            buffer.position(0).limit(n * RECORD)
            var pos = start * RECORD
            named { while (block.hasRemaining()) pos += channel.write(block, pos) }
            end = start
        }
        buffer.clear()
    }

    /** [visit] (block, offset of the record) for every record from the first to the last. */
    inline fun forward(visit: (ByteBuffer, Int) -> Unit) {
        var start = 0L
        while (start < records) {
            val n = minOf(BLOCK.toLong(), records - start).toInt()
            read(start, n)
            for (i in 0 until n) visit(block, i * RECORD)
            start += n
        }
        buffer.clear()
    }

    fun read(start: Long, n: Int) {
        buffer.clear().limit(n * RECORD)
        var pos = start * RECORD
        while (block.hasRemaining()) {
            val r = channel.read(block, pos)
            if (r < 0) throw IOException("offline replay: the temporary file ended early")
            pos += r
        }
    }

    override fun close() {
        if (closed) return
        closed = true
        try {
            channel.close()
        } finally {
            if (!unlinked) {
                Files.deleteIfExists(path)
                TemporaryFiles.remove(path)
            }
        }
    }

    companion object {
        const val RECORD = 184
        const val BLOCK = 2048
        const val TIME = 16
        const val GYRO = 24
        const val ACC = 48
        const val MAG = 72
        const val Q = 96
        const val RECENT = 128
        const val KX = 136
        const val KB = 144
        const val KP11 = 152
        const val KP12 = 160
        const val KP22 = 168
        const val KU = 176
        const val VALUES = 16
        const val MAX_VALUES = 14
    }
}
