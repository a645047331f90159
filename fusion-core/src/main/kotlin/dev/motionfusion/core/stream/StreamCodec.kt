package dev.motionfusion.core.stream

import dev.motionfusion.core.Orientations
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.Json
import dev.motionfusion.core.io.JsonObject
import dev.motionfusion.core.session.MetadataJson

/**
 * The JSON form of [StreamMessage] (docs/STREAMING.md): one object per message, `type` first.
 * Numbers round-trip exactly: floats as Float.toString, doubles as Double.toString, timestamps as
 * integers. [decode] reports malformed or unknown messages as [DataFormatException] naming the
 * source, line and column.
 */
public object StreamCodec {
    /** The schema version this library writes and the newest it reads. */
    public const val SCHEMA_VERSION: Int = 1

    /** The stream name of the fused orientation in requests and `hello` (the session format's `orientation`). */
    public val ORIENTATION: SessionStream = SessionStream.ORIENTATION

    /** The streams a phone can offer: the session format's sensor streams and the orientation. */
    public val STREAMABLE: List<SessionStream> = SessionStream.entries.filter { it != SessionStream.TRUTH }

    @JvmStatic
    public fun encode(m: StreamMessage): String = StringBuilder(128).also { encodeTo(it, m) }.toString()

    /** Appends the JSON of [m] to [sb] (one line, no trailing newline). */
    @JvmStatic
    public fun encodeTo(sb: StringBuilder, m: StreamMessage) {
        when (m) {
            is StreamMessage.Sample -> {
                sb.append("{\"type\":\"sample\",\"stream\":\"").append(m.stream.key).append("\",\"t\":").append(m.timestampNs).append(",\"v\":[")
                for (i in m.values.indices) {
                    if (i > 0) sb.append(',')
                    float(sb, m.values[i])
                }
                sb.append(']')
                if (m.accuracy != StreamMessage.Sample.NO_ACCURACY) sb.append(",\"a\":").append(m.accuracy)
                sb.append('}')
            }
            is StreamMessage.Orientation -> {
                val q = doubleArrayOf(m.qw, m.qx, m.qy, m.qz)
                val angles = DoubleArray(6)
                Orientations.androidAndAerospaceAngles(q, angles, 0)
                sb.append("{\"type\":\"orientation\",\"t\":").append(m.timestampNs).append(",\"q\":[")
                double(sb, m.qw).append(',')
                double(sb, m.qx).append(',')
                double(sb, m.qy).append(',')
                double(sb, m.qz).append("],\"azimuth_deg\":")
                double(sb, Math.toDegrees(angles[0])).append(",\"pitch_deg\":")
                double(sb, Math.toDegrees(angles[1])).append(",\"roll_deg\":")
                double(sb, Math.toDegrees(angles[2])).append('}')
            }
            is StreamMessage.Status -> {
                sb.append("{\"type\":\"status\",\"t\":").append(m.timestampNs).append(",\"sent\":").append(m.sent)
                    .append(",\"dropped\":").append(m.dropped).append(",\"rate_hz\":")
                double(sb, m.rateHz).append('}')
            }
            is StreamMessage.Pair -> {
                sb.append("{\"type\":\"pair\",\"schema\":").append(m.schema).append(",\"code\":")
                sb.append(Json.write(m.code).trim())
                m.streams?.let { s -> sb.append(",\"streams\":[").append(s.joinToString(",") { "\"${it.key}\"" }).append(']') }
                m.rateHz?.let { sb.append(",\"rate_hz\":"); double(sb, it) }
                m.client?.let { sb.append(",\"client\":").append(Json.write(it).trim()) }
                sb.append('}')
            }
            is StreamMessage.Hello -> {
                sb.append("{\"type\":\"hello\",\"schema\":").append(m.schema).append(",\"source\":").append(Json.write(m.source).trim())
                sb.append(",\"streams\":[").append(m.streams.joinToString(",") { "\"${it.key}\"" }).append("],\"rate_hz\":")
                if (m.rateHz == null) sb.append("null") else double(sb, m.rateHz)
                if (m.clock) sb.append(",\"clock\":true")
                sb.append(",\"meta\":").append(Json.write(MetadataJson.toMap(m.metadata), indent = "").replace("\n", "")).append('}')
            }
            is StreamMessage.Error -> sb.append("{\"type\":\"error\",\"reason\":").append(Json.write(m.reason).trim()).append('}')
            is StreamMessage.Waiting -> sb.append("{\"type\":\"waiting\",\"reason\":").append(Json.write(m.reason).trim()).append('}')
            is StreamMessage.Ping -> {
                sb.append("{\"type\":\"ping\",\"id\":").append(m.id).append(",\"t1\":").append(m.t1Ns)
                if (m.previousId != null && m.previousT4Ns != null) sb.append(",\"previous_id\":").append(m.previousId).append(",\"previous_t4\":").append(m.previousT4Ns)
                m.laptopClock?.let { sb.append(",\"clock\":").append(Json.write(it).trim()) }
                sb.append('}')
            }
            is StreamMessage.Control -> {
                sb.append("{\"type\":\"control\",\"id\":").append(m.id).append(",\"command\":\"").append(m.command.key).append("\",\"t\":").append(m.laptopNs)
                m.atNs?.let { sb.append(",\"at\":").append(it) }
                m.laptopClock?.let { sb.append(",\"clock\":").append(Json.write(it).trim()) }
                m.label?.let { sb.append(",\"label\":").append(Json.write(it).trim()) }
                sb.append('}')
            }
            is StreamMessage.ControlResult -> {
                sb.append("{\"type\":\"control_result\",\"id\":").append(m.id).append(",\"ok\":").append(m.ok)
                m.reason?.let { sb.append(",\"reason\":").append(Json.write(it).trim()) }
                m.session?.let { sb.append(",\"session\":").append(Json.write(it).trim()) }
                sb.append('}')
            }
            is StreamMessage.Pong -> sb.append("{\"type\":\"pong\",\"id\":").append(m.id).append(",\"t1\":").append(m.t1Ns)
                .append(",\"t2\":").append(m.t2Ns).append(",\"t3\":").append(m.t3Ns).append('}')
        }
    }

    /**
     * The message in [text]; [source] names where it came from in errors (e.g. "ws://host:port").
     * A message of a newer schema, an unknown type or stream, or a malformed value is an error.
     */
    @JvmStatic
    public fun decode(text: String, source: String): StreamMessage {
        val o = Json.document(text, source).rootObject()
        return when (val type = o.string("type")) {
            "sample" -> {
                val stream = stream(o, "stream", o.string("stream"))
                if (stream == SessionStream.ORIENTATION) throw o.error("stream", "the orientation comes as type \"orientation\"")
                val v = o.raw("v") as? List<*> ?: throw o.error("v", "expected an array of numbers")
                if (v.size != stream.valueCount && !(stream.valueCount - v.size == 1 && stream == SessionStream.ROTATION_VECTOR)) {
                    throw o.error("v", "${stream.key} has ${stream.valueCount} values, got ${v.size}")
                }
                val values = FloatArray(v.size) { i ->
                    when (val x = v[i]) {
                        null -> Float.NaN
                        is Number -> x.toDouble().toFloat()
                        else -> throw o.error("v", "element $i is not a number")
                    }
                }
                val accuracy = if (stream.hasAccuracy) o.int("a", -1) else StreamMessage.Sample.NO_ACCURACY
                StreamMessage.Sample(stream, timestamp(o), values, accuracy)
            }
            "orientation" -> {
                val q = o.numbers("q", 4)
                StreamMessage.Orientation(timestamp(o), q[0], q[1], q[2], q[3])
            }
            "status" -> StreamMessage.Status(timestamp(o), o.long("sent", 0), o.long("dropped", 0), o.double("rate_hz"))
            "error" -> StreamMessage.Error(o.string("reason"))
            "waiting" -> StreamMessage.Waiting(o.string("reason"))
            "ping" -> StreamMessage.Ping(required(o, "id"), required(o, "t1"), o.longOrNull("previous_id"), o.longOrNull("previous_t4"), o.stringOrNull("clock"))
            "pong" -> StreamMessage.Pong(required(o, "id"), required(o, "t1"), required(o, "t2"), required(o, "t3"))
            "control" -> {
                val name = o.string("command")
                StreamMessage.Control(
                    required(o, "id"),
                    StreamMessage.Control.Command.entries.firstOrNull { it.key == name }
                        ?: throw o.error("command", "unknown command \"$name\" (known: start, stop, mark)"),
                    required(o, "t"), o.longOrNull("at"), o.stringOrNull("clock"), o.stringOrNull("label"),
                )
            }
            "control_result" -> StreamMessage.ControlResult(
                required(o, "id"), o.raw("ok") as? Boolean ?: throw o.error("ok", "missing: true or false"), o.stringOrNull("reason"), o.stringOrNull("session"),
            )
            "pair" -> StreamMessage.Pair(
                code = o.stringOrNull("code") ?: throw o.error("code", "missing: the pairing code shown on the phone"),
                streams = streams(o),
                rateHz = rate(o),
                schema = schema(o),
                client = o.stringOrNull("client"),
            )
            "hello" -> {
                val meta = o.raw("meta") as? Map<*, *> ?: throw o.error("meta", "missing or not an object")
                StreamMessage.Hello(
                    source = o.string("source"),
                    metadata = MetadataJson.parse(Json.write(meta), "$source (hello.meta)"),
                    streams = streams(o) ?: emptyList(),
                    rateHz = rate(o),
                    schema = schema(o),
                    clock = o.raw("clock") == true,
                )
            }
            else -> throw o.error("type", if (type.isEmpty()) "missing" else "unknown message type \"$type\"")
        }
    }

    private fun required(o: JsonObject, key: String): Long = o.longOrNull(key) ?: throw o.error(key, "missing: an integer")

    private fun timestamp(o: JsonObject): Long = o.longOrNull("t") ?: throw o.error("t", "missing: the sensor timestamp in ns")

    private fun schema(o: JsonObject): Int {
        val s = o.int("schema", -1)
        if (s < 1) throw o.error("schema", "missing or not a positive integer")
        if (s > SCHEMA_VERSION) throw o.error("schema", "$s is newer than this reader ($SCHEMA_VERSION); update fusion")
        return s
    }

    private fun rate(o: JsonObject): Double? {
        val r = o.double("rate_hz", Double.NaN)
        if (r.isNaN()) return null
        if (!(r > 0.0 && r.isFinite())) throw o.error("rate_hz", "expected a positive number of Hz")
        return r
    }

    private fun streams(o: JsonObject): List<SessionStream>? {
        val raw = o.raw("streams") ?: return null
        val list = raw as? List<*> ?: throw o.error("streams", "expected an array of stream names")
        return list.map { name -> stream(o, "streams", name as? String ?: throw o.error("streams", "expected stream names")) }
    }

    private fun stream(o: JsonObject, key: String, name: String): SessionStream =
        SessionStream.ofKey(name)?.takeIf { it in STREAMABLE }
            ?: throw o.error(key, "unknown stream \"$name\" (known: ${STREAMABLE.joinToString(", ") { it.key }})")

    private fun float(sb: StringBuilder, f: Float) {
        if (f.isFinite()) sb.append(f) else sb.append("null")
    }

    private fun double(sb: StringBuilder, d: Double): StringBuilder = if (d.isFinite()) sb.append(d) else sb.append("null")
}
