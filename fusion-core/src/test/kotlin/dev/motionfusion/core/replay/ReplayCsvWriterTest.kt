package dev.motionfusion.core.replay

import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test
import dev.motionfusion.core.io.AsciiNumbers
import java.io.ByteArrayOutputStream
import java.io.IOException
import java.io.OutputStream
import java.util.Random

class ReplayCsvWriterTest {
    /** Steps of a random walk of orientations, some not yet initialised (NaN), with flushes between. */
    private fun write(parallel: Boolean, out: OutputStream, rows: Int, flushEvery: Int = 0): Long {
        val r = Random(12)
        val step = ReplayStep()
        val w = ReplayCsvWriter(out, true, parallel)
        w.use {
            for (i in 0 until rows) {
                step.timeS = i * 0.0016366
                if (i < 50) {
                    step.orientation.fill(Double.NaN)
                } else {
                    var n = 0.0
                    for (k in 0 until 4) { step.orientation[k] = r.nextGaussian(); n += step.orientation[k] * step.orientation[k] }
                    for (k in 0 until 4) step.orientation[k] /= Math.sqrt(n)
                }
                for (k in 0 until 3) step.specificForce[k] = r.nextGaussian() * 4 + if (k == 2) 9.8 else 0.0
                it.step(step)
                if (flushEvery > 0 && i % flushEvery == 0) it.flush()
            }
        }
        return w.rows
    }

    @Test
    fun `formatting on a second thread writes the same bytes`() {
        for ((rows, flushEvery) in listOf(0 to 0, 1 to 0, 4095 to 0, 4096 to 0, 4097 to 0, 50_000 to 0, 30_000 to 7_001)) {
            val serial = ByteArrayOutputStream()
            val parallel = ByteArrayOutputStream()
            assertEquals(rows.toLong(), write(false, serial, rows, flushEvery))
            assertEquals(rows.toLong(), write(true, parallel, rows, flushEvery))
            assertArrayEquals(serial.toByteArray(), parallel.toByteArray(), "$rows rows")
        }
    }

    @Test
    fun `every column is its own value's text, also where the writer copies one angle's text for another`() {
        val r = Random(3)
        val h = Math.sqrt(0.5)
        val special = listOf(
            doubleArrayOf(1.0, 0.0, 0.0, 0.0), // all angles 0
            doubleArrayOf(h, h, 0.0, 0.0), doubleArrayOf(h, -h, 0.0, 0.0), // top edge up / down: gimbal lock
            doubleArrayOf(0.5, 0.5, 0.5, 0.5), // top edge up too
            doubleArrayOf(Math.cos(1e-7), Math.sin(1e-7), 0.0, 0.0), // pitch rounding to 0
            doubleArrayOf(Math.cos(-2e-6), Math.sin(-2e-6), 0.0, 0.0), doubleArrayOf(Double.NaN, Double.NaN, Double.NaN, Double.NaN),
        )
        val qs = special + List(20_000) {
            val q = DoubleArray(4) { r.nextGaussian() * if (it == 2 && r.nextInt(4) == 0) 1e-6 else 1.0 }
            val n = Math.sqrt(q.sumOf { it * it })
            DoubleArray(4) { q[it] / n }
        }
        val out = ByteArrayOutputStream()
        val step = ReplayStep()
        ReplayCsvWriter(out).use { w ->
            for (q in qs) {
                q.copyInto(step.orientation)
                for (k in 0 until 3) step.specificForce[k] = r.nextGaussian()
                w.step(step)
            }
        }
        val lines = out.toString("US-ASCII").lines().drop(1).filter { it.isNotEmpty() }
        assertEquals(qs.size, lines.size)
        val angles = DoubleArray(9)
        var gimbalLock = 0
        for ((i, q) in qs.withIndex()) {
            val fields = lines[i].split(',')
            ReplayCsvWriter.derived(q, doubleArrayOf(0.0, 0.0, 0.0), angles) // the angles depend on q alone
            if (angles[3] != angles[0] && !q[0].isNaN()) gimbalLock++
            for (k in 0 until 6) assertEquals(AsciiNumbers.fixedToString(angles[k], 4), fields[5 + k], "row $i column ${5 + k}")
        }
        assertEquals(3, gimbalLock, "the three orientations with the top edge vertical (gimbal lock)")
    }

    @Test
    fun `a failing output is reported by the writer on the caller's thread`() {
        for (parallel in listOf(false, true)) {
            val full = object : OutputStream() {
                var written = 0L
                override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)
                override fun write(b: ByteArray, off: Int, len: Int) {
                    written += len
                    if (written > 1_000_000) throw IOException("No space left on device")
                }
            }
            val e = assertThrows(IOException::class.java) { write(parallel, full, 100_000) }
            assertEquals("No space left on device", e.message)
        }
    }
}
