package dev.motionfusion.core.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.DeviceInfo
import dev.motionfusion.core.session.SessionMetadata
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import kotlin.random.Random

class StreamCodecTest {
    private fun roundTrip(m: StreamMessage): StreamMessage = StreamCodec.decode(StreamCodec.encode(m), "test")

    @Test
    fun `samples round-trip bit for bit, every stream, random and extreme floats`() {
        val rnd = Random(7)
        val extremes = floatArrayOf(0f, -0f, Float.MIN_VALUE, -Float.MIN_VALUE, Float.MAX_VALUE, 1e-38f, 9.80665f, 0.1f, 16777217f, -3.4028235e38f)
        val streams = StreamCodec.STREAMABLE - SessionStream.ORIENTATION
        repeat(200_000) { i ->
            val stream = streams[i % streams.size]
            val values = FloatArray(stream.valueCount) {
                if (i % 10 == 0) extremes[(i + it) % extremes.size] else Float.fromBits(rnd.nextInt()).takeIf { f -> f.isFinite() } ?: rnd.nextFloat()
            }
            val accuracy = if (stream.hasAccuracy) rnd.nextInt(-1, 4) else StreamMessage.Sample.NO_ACCURACY
            val m = StreamMessage.Sample(stream, rnd.nextLong(), values, accuracy)
            val back = roundTrip(m) as StreamMessage.Sample
            assertEquals(m, back)
            for (k in values.indices) assertEquals(values[k].toRawBits(), back.values[k].toRawBits(), "$m value $k")
        }
    }

    @Test
    fun `orientations round-trip exactly and carry Android's angles`() {
        val rnd = Random(3)
        repeat(20_000) {
            val q = DoubleArray(4) { rnd.nextDouble(-1.0, 1.0) }
            val n = kotlin.math.sqrt(q.sumOf { it * it })
            val m = StreamMessage.Orientation(rnd.nextLong(0, Long.MAX_VALUE), q[0] / n, q[1] / n, q[2] / n, q[3] / n)
            assertEquals(m, roundTrip(m))
        }
        // Phone flat, top edge pointing east: azimuth 90°, pitch 0, roll 0 (sensor → ENU turned −90° about up).
        val s = Math.sqrt(0.5)
        val text = StreamCodec.encode(StreamMessage.Orientation(5, s, 0.0, 0.0, -s))
        val azimuth = Regex("\"azimuth_deg\":([-0-9.E]+)").find(text)!!.groupValues[1].toDouble()
        assertEquals(90.0, azimuth, 1e-9, text)
    }

    @Test
    fun `pair, hello, status and error round-trip`() {
        val meta = SessionMetadata(
            appVersion = "0.1.0",
            source = "Motion Fusion 0.1.0",
            device = DeviceInfo(manufacturer = "Maker \"Q\"", model = "Ph\none", sdkInt = 35),
            startAnchor = ClockAnchor(1_764_000_000_123, 987_654_321_000),
            filterSettings = FilterSettings(),
        )
        val messages = listOf(
            StreamMessage.Pair("123456"),
            StreamMessage.Pair("00ä", listOf(SessionStream.GYROSCOPE, SessionStream.ORIENTATION), 50.0),
            StreamMessage.Hello("Motion Fusion 0.1.0", meta, listOf(SessionStream.ACCELEROMETER, SessionStream.ORIENTATION), null),
            StreamMessage.Hello("x", meta, StreamCodec.STREAMABLE, 12.5),
            StreamMessage.Status(77, 1000, 3, 199.5),
            StreamMessage.Error("pairing code wrong"),
            StreamMessage.Pair("123456", client = "fusion listen on \"lab\" ä"),
            StreamMessage.Waiting("the phone asks its user to allow this client"),
            StreamMessage.Control(1, StreamMessage.Control.Command.START, 123_456_789_012_345, 81_234_567_890_123, "lab-laptop boot 1f2e"),
            StreamMessage.Control(2, StreamMessage.Control.Command.STOP, -5),
            StreamMessage.Control(3, StreamMessage.Control.Command.MARK, 7, 8, label = "jump \"2\" ä"),
            StreamMessage.ControlResult(1, true, session = "2026-12-06_10-55-07"),
            StreamMessage.ControlResult(2, false, "remote control is off on the phone"),
        )
        for (m in messages) {
            val text = StreamCodec.encode(m)
            assertTrue('\n' !in text, text)
            assertEquals(m, StreamCodec.decode(text, "test"))
        }
    }

    @Test
    fun `malformed and newer messages are errors naming the place`() {
        fun error(text: String): String = assertThrows<DataFormatException> { StreamCodec.decode(text, "ws://phone") }.message!!
        assertEquals("ws://phone:1:9: type: unknown message type \"nope\"", error("""{"type":"nope"}"""))
        assertTrue("newer than this reader" in error("""{"type":"pair","schema":2,"code":"1"}"""))
        assertTrue("unknown stream \"barometer\"" in error("""{"type":"sample","stream":"barometer","t":1,"v":[1]}"""))
        assertTrue("gyroscope has 3 values, got 2" in error("""{"type":"sample","stream":"gyroscope","t":1,"v":[1,2]}"""))
        assertTrue("t: missing" in error("""{"type":"sample","stream":"gyroscope","v":[1,2,3]}"""))
        assertTrue("code: missing" in error("""{"type":"pair","schema":1}"""))
        assertTrue("rate_hz: expected a positive" in error("""{"type":"pair","schema":1,"code":"1","rate_hz":-5}"""))
        assertTrue("expected a JSON object" in error("""[1]"""))
        assertTrue("unknown command \"reboot\"" in error("""{"type":"control","id":1,"command":"reboot","t":1}"""))
        assertTrue("t: missing" in error("""{"type":"control","id":1,"command":"start"}"""))
        assertTrue("ok: missing" in error("""{"type":"control_result","id":1}"""))
    }
}
