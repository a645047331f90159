package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows

class EventRingTest {
    private class Row(val stream: SessionStream, val t: Long, val accuracy: Int, val values: List<Float>, val afterGap: Boolean = false)

    private fun EventRing.drainAll(): List<Row> {
        val out = ArrayList<Row>()
        drain({ s, t, a, v, o, gap -> out += Row(s, t, a, (0 until SensorStreams.maxValues).map { v[o + it] }, gap) })
        return out
    }

    @Test
    fun `events come out in order with their values, accuracy and NaN padding`() {
        val ring = EventRing(8)
        assertTrue(ring.offer(SessionStream.ACCELEROMETER, 10, 3, floatArrayOf(1f, 2f, 3f), 3))
        assertTrue(ring.offer(SessionStream.ROTATION_VECTOR, 11, -1, floatArrayOf(0.1f, 0.2f, 0.3f, 0.9f), 4))
        assertTrue(ring.offer(SessionStream.GYROSCOPE_UNCALIBRATED, 12, 0, floatArrayOf(1f, 2f, 3f, 4f, 5f, 6f, 7f), 7))
        val rows = ring.drainAll()
        assertEquals(listOf(10L, 11L, 12L), rows.map { it.t })
        assertEquals(listOf(3, -1, 0), rows.map { it.accuracy })
        assertEquals(listOf(1f, 2f, 3f), rows[0].values.take(3))
        assertTrue(rows[0].values.drop(3).all { it.isNaN() })
        assertEquals(listOf(0.1f, 0.2f, 0.3f, 0.9f), rows[1].values.take(4))
        assertTrue(rows[1].values[4].isNaN(), "missing heading accuracy is NaN")
        assertEquals(listOf(1f, 2f, 3f, 4f, 5f, 6f), rows[2].values, "only valueCount values are kept")
        assertEquals(0, ring.size)
    }

    @Test
    fun `wraps around many times`() {
        val ring = EventRing(4)
        var next = 0L
        var expected = 0L
        repeat(100) {
            repeat(3) { assertTrue(ring.offer(SessionStream.GYROSCOPE, next++, 3, floatArrayOf(0f, 0f, 0f), 3)) }
            for (r in ring.drainAll()) assertEquals(expected++, r.t)
        }
        assertEquals(300L, expected)
    }

    @Test
    fun `a full ring refuses, and the next event it takes carries the gap`() {
        val ring = EventRing(4)
        val v = floatArrayOf(0f, 0f, 0f)
        repeat(4) { assertTrue(ring.offer(SessionStream.GYROSCOPE, it.toLong(), 3, v, 3)) }
        assertFalse(ring.offer(SessionStream.GYROSCOPE, 4, 3, v, 3))
        assertFalse(ring.offer(SessionStream.GYROSCOPE, 5, 3, v, 3))
        assertEquals(listOf(false, false, false, false), ring.drainAll().map { it.afterGap })
        assertTrue(ring.offer(SessionStream.GYROSCOPE, 6, 3, v, 3), "space freed: the live screen goes on")
        assertTrue(ring.offer(SessionStream.GYROSCOPE, 7, 3, v, 3))
        assertEquals(listOf(6L to true, 7L to false), ring.drainAll().map { it.t to it.afterGap })
        assertEquals(2L, ring.refused)
    }

    @Test
    fun `a consumer that throws leaves its event queued`() {
        val ring = EventRing(4)
        val v = floatArrayOf(0f, 0f, 0f)
        repeat(3) { ring.offer(SessionStream.GYROSCOPE, it.toLong(), 3, v, 3) }
        var seen = 0
        assertThrows<IllegalStateException> {
            ring.drain({ _, t, _, _, _, _ -> if (t == 1L) error("disk"); seen++ })
        }
        assertEquals(1, seen)
        assertEquals(listOf(1L, 2L), ring.drainAll().map { it.t })
    }

    @Test
    fun `capacity must be a power of two`() {
        assertThrows<IllegalArgumentException> { EventRing(6) }
        assertThrows<IllegalArgumentException> { EventRing(1) }
    }

    @Test
    fun `producer and consumer threads pass 2,000,000 events without loss or reordering`() {
        val ring = EventRing(1 shl 12)
        val n = 2_000_000L
        val producer = Thread {
            val v = FloatArray(6)
            var i = 0L
            while (i < n) {
                v[0] = i.toFloat()
                // A producer that never waits: spin only because this test wants every event.
                if (ring.size < ring.capacity) {
                    check(ring.offer(SensorStreams.all[(i % 7).toInt()], i, 3, v, 6))
                    i++
                }
            }
        }
        producer.start()
        var expected = 0L
        var bad = 0L
        while (expected < n) {
            ring.drain({ s, t, _, vs, o, _ ->
                if (t != expected || s != SensorStreams.all[(t % 7).toInt()] || vs[o] != t.toFloat()) bad++
                expected++
            })
        }
        producer.join()
        assertEquals(0L, bad)
        assertEquals(n, expected)
        assertEquals(0L, ring.refused)
    }
}
