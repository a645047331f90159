/*
 * The live stream's messages (docs/STREAMING.md): what the phone sends to a laptop while it
 * captures, and what a laptop asks for. One JSON object per WebSocket text frame; the values are
 * those of the session format (docs/SESSION_FORMAT.md): the same stream names, columns, units and
 * frames, SensorEvent.timestamp in ns, the orientation sensor → ENU [w, x, y, z].
 */
package dev.motionfusion.core.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionMetadata

/** A message of the streaming schema, version [StreamCodec.SCHEMA_VERSION]. */
public sealed class StreamMessage {
    /**
     * Client → phone, the first message of a connection: the pairing [code] shown on the phone,
     * the [streams] wanted (null: every stream the phone offers) and the highest rate per stream
     * in Hz ([rateHz], null: every sample), and optionally the [client]'s name, which the phone shows when it asks
     * its user to allow a new client ("fusion listen on lab-laptop"; a claim of the client, not checked).
     */
    public data class Pair @JvmOverloads constructor(
        val code: String,
        val streams: List<SessionStream>? = null,
        val rateHz: Double? = null,
        val schema: Int = StreamCodec.SCHEMA_VERSION,
        val client: String? = null,
    ) : StreamMessage()

    /**
     * Phone → client, once the pairing code was right: the session metadata as meta.json holds it
     * ([metadata]: device, sensors, the clock anchor read when capture started, the live filter's
     * settings), the [streams] this client gets and its [rateHz] (null: every sample).
     */
    public data class Hello @JvmOverloads constructor(
        val source: String,
        val metadata: SessionMetadata,
        val streams: List<SessionStream>,
        val rateHz: Double?,
        val schema: Int = StreamCodec.SCHEMA_VERSION,
        /** Whether the phone answers [Ping] with [Pong] (phones before it ignore pings: a client pings only when true). */
        val clock: Boolean = false,
    ) : StreamMessage()

    /**
     * One sensor sample: [values] as SensorEvent.values (the session format's columns, without the
     * accuracy), [accuracy] the SensorEvent accuracy (−1…3; [NO_ACCURACY] for streams without one).
     */
    public class Sample(
        public val stream: SessionStream,
        public val timestampNs: Long,
        public val values: FloatArray,
        public val accuracy: Int,
    ) : StreamMessage() {
        override fun equals(other: Any?): Boolean = other is Sample && stream == other.stream &&
            timestampNs == other.timestampNs && values.contentEquals(other.values) && accuracy == other.accuracy

        override fun hashCode(): Int = ((stream.hashCode() * 31 + timestampNs.hashCode()) * 31 + values.contentHashCode()) * 31 + accuracy

        override fun toString(): String = "Sample($stream, $timestampNs, ${values.contentToString()}, $accuracy)"

        public companion object {
            /** The accuracy of a sample whose stream has none. */
            public const val NO_ACCURACY: Int = Int.MIN_VALUE
        }
    }

    /** The fused orientation at [timestampNs]: sensor → ENU, Hamilton, [w, x, y, z] (the screen's and the recording's filter). */
    public data class Orientation(val timestampNs: Long, val qw: Double, val qx: Double, val qy: Double, val qz: Double) : StreamMessage()

    /**
     * Phone → client about once a second of sample time: messages [sent] to this client so far,
     * [dropped] because it did not keep up (its queue was full) or because the phone's own hand-off
     * queue overflowed, and the rate it got over the last second, messages per second.
     */
    public data class Status(val timestampNs: Long, val sent: Long, val dropped: Long, val rateHz: Double) : StreamMessage()

    /** Phone → client before it closes the connection: why ("pairing code wrong", "unknown stream …"). */
    public data class Error(val reason: String) : StreamMessage()

    /**
     * Phone → client after a right code, before the hello, when the phone asks its user to allow this client: what it
     * waits for ([reason]). The hello follows once allowed; a refusal is an [Error] and the close.
     */
    public data class Waiting(val reason: String) : StreamMessage()

    /**
     * Client → phone, after the hello, to put the phone's clock on the client's (docs/SYNC.md): exchange [id], sent
     * at [t1Ns] on the client's monotonic clock. [previousId] and [previousT4Ns], when given, say when the answer to
     * the client's previous ping arrived, so that the phone holds whole exchanges too. [laptopClock], when given, names
     * the client's clock (as meta.json's `clock_link`), so that a phone recording while linked names it in its session.
     */
    public data class Ping @JvmOverloads constructor(
        val id: Long,
        val t1Ns: Long,
        val previousId: Long? = null,
        val previousT4Ns: Long? = null,
        val laptopClock: String? = null,
    ) : StreamMessage()

    /**
     * Phone → client, the answer to [Ping] [id]: its [t1Ns] back, and when the phone received it ([t2Ns]) and answered
     * ([t3Ns]), on the phone's sensor clock (elapsedRealtimeNanos, the clock of every sample's timestamp).
     */
    public data class Pong(val id: Long, val t1Ns: Long, val t2Ns: Long, val t3Ns: Long) : StreamMessage()

    /**
     * Client → phone, after the hello: start or stop a recording on the phone, or mark a moment in it (docs/STREAMING.md,
     * "Remote control"). The phone carries it out only when its user allowed remote control; otherwise it answers with a
     * refusal and closes the connection. [laptopNs] is the command's instant on the client's monotonic clock (the clock of
     * its pings, named by [laptopClock], as meta.json's `clock_link` names it); [atNs] the same instant on the phone's
     * sensor clock as the client's clock exchanges estimate it (null: when the phone receives it). A start with [atNs]
     * keeps no sample before it, so that phones started together begin together; a mark is set there. [label] is a mark's
     * note.
     */
    public data class Control @JvmOverloads constructor(
        val id: Long,
        val command: Command,
        val laptopNs: Long,
        val atNs: Long? = null,
        val laptopClock: String? = null,
        val label: String? = null,
    ) : StreamMessage() {
        /** What a [Control] asks for; [key] is its name in the message. */
        public enum class Command(public val key: String) { START("start"), STOP("stop"), MARK("mark") }
    }

    /**
     * Phone → client, the answer to [Control] [id]: [ok] when it was carried out, else [reason] ("already recording",
     * "remote control is off on the phone"); [session] names the recording it concerns, when there is one.
     */
    public data class ControlResult @JvmOverloads constructor(val id: Long, val ok: Boolean, val reason: String? = null, val session: String? = null) : StreamMessage()
}
