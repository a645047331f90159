package dev.motionfusion.app.ui

import android.content.Context
import android.graphics.Canvas
import android.graphics.Color
import android.graphics.DashPathEffect
import android.graphics.Paint
import android.graphics.Path
import android.util.AttributeSet
import android.view.View
import com.google.android.material.R as MaterialR
import dev.motionfusion.app.R
import dev.motionfusion.core.Quaternion
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.min
import kotlin.math.sin

/**
 * The phone as a shaded 3D model turned by the fused orientation, seen from a fixed camera in
 * the earth frame ([PhoneMesh]: south of the phone, above it, looking north): a compass ring on
 * the ground marks N, E, S, W, so a phone flat on a table with its top towards north lies screen
 * up with its top edge away from the viewer. The phone's own rotation vector, when given, is
 * drawn as a dashed outline (the "ghost") in the same place: where the two disagree, the ghost
 * stands apart. Without an orientation the model is dimmed. Nothing is allocated per frame.
 */
class PhoneModelView @JvmOverloads constructor(context: Context, attrs: AttributeSet? = null) : View(context, attrs) {
    private val mesh = PhoneMesh()
    private val ghostMesh = PhoneMesh()
    private var orientation: Quaternion? = null
    private var ghost: Quaternion? = null

    private val density = resources.displayMetrics.density
    private val fill = Paint(Paint.ANTI_ALIAS_FLAG).apply { style = Paint.Style.FILL }
    private val edge = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        style = Paint.Style.STROKE; strokeWidth = 1.2f * density; strokeJoin = Paint.Join.ROUND
    }
    private val ghostPaint = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        style = Paint.Style.STROKE; strokeWidth = 1.6f * density
        pathEffect = DashPathEffect(floatArrayOf(6f * density, 4f * density), 0f)
        color = themeColor(MaterialR.attr.colorTertiary, Color.MAGENTA)
    }
    private val ring = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        style = Paint.Style.STROKE; strokeWidth = 1f * density
        color = themeColor(MaterialR.attr.colorOutline, Color.GRAY)
    }
    private val cardinal = Paint(Paint.ANTI_ALIAS_FLAG).apply {
        textAlign = Paint.Align.CENTER; textSize = sp(13f)
        color = themeColor(MaterialR.attr.colorOnSurfaceVariant, Color.GRAY)
    }
    private val north = Paint(cardinal).apply { color = context.getColor(R.color.compass_north); isFakeBoldText = true }
    private val path = Path()
    private val p = FloatArray(2)
    private val cardinals = cardinalPoints(context)

    private val bodyColour = themeColor(MaterialR.attr.colorPrimary, Color.DKGRAY)
    private val screenColour = Color.rgb(0x1C, 0x26, 0x36)
    private val frontCameraColour = Color.rgb(0x5A, 0x66, 0x78)
    private val lensColour = Color.rgb(0x08, 0x0A, 0x0E)
    private val outlineColour = themeColor(MaterialR.attr.colorOnSurface, Color.BLACK)

    /**
     * Shows [orientation] (device → ENU, null before the first estimate) and the phone's own
     * rotation vector as a ghost ([ghost], device → ENU, null when there is none).
     */
    fun setOrientation(orientation: Quaternion?, ghost: Quaternion?) {
        this.orientation = orientation
        this.ghost = ghost
        invalidate()
    }

    /**
     * Whether the heading has a north (false in 6D, without a magnetometer: the heading's zero is the
     * start's). Without one the ground ring is drawn without its cardinal points, as the compass then
     * shows degrees.
     */
    var northKnown: Boolean = true
        set(value) {
            if (field != value) { field = value; invalidate() }
        }

    override fun onMeasure(widthMeasureSpec: Int, heightMeasureSpec: Int) {
        val w = MeasureSpec.getSize(widthMeasureSpec)
        // As tall as wide up to the dial's size: a phone standing upright must fit.
        setMeasuredDimension(w, resolveSize(min(w, (MAX_DIAL_DP * density).toInt()), heightMeasureSpec))
    }

    override fun onDraw(canvas: Canvas) {
        // A half length of the phone in pixels, so that the ring and its labels (±1.5 across,
        // −1.15..1.7 down the view for the camera's 35°) fit; centred on that extent.
        val scale = min(width / 3.3f, height / 3.1f)
        val cx = width / 2f
        val cy = height / 2f - 0.27f * scale
        drawGround(canvas, cx, cy, scale)
        val q = orientation ?: Quaternion.IDENTITY
        val alpha = if (orientation == null) 0x60 else 0xFF
        mesh.project(q)
        for (i in 0 until mesh.drawCount) {
            val f = mesh.order[i]
            face(f, mesh, cx, cy, scale)
            fill.color = shaded(colourOf(mesh.part(f)), mesh.shade[f], alpha)
            canvas.drawPath(path, fill)
            if (mesh.part(f) != PhoneMesh.Part.LENS && mesh.part(f) != PhoneMesh.Part.FRONT_CAMERA) {
                edge.color = outlineColour
                edge.alpha = alpha * 0x50 / 0xFF
                canvas.drawPath(path, edge)
            }
        }
        val g = ghost ?: return
        ghostMesh.project(g)
        for (i in 0 until ghostMesh.drawCount) {
            val f = ghostMesh.order[i]
            val part = ghostMesh.part(f)
            if (part == PhoneMesh.Part.LENS || part == PhoneMesh.Part.SCREEN || part == PhoneMesh.Part.FRONT_CAMERA) continue
            face(f, ghostMesh, cx, cy, scale)
            canvas.drawPath(path, ghostPaint)
        }
    }

    /** A ring on the ground below the phone with the four cardinal points (ENU: E = x, N = y) when [northKnown]. */
    private fun drawGround(canvas: Canvas, cx: Float, cy: Float, scale: Float) {
        val radius = 1.25f
        val down = -0.9f
        path.rewind()
        for (k in 0..48) {
            val a = 2.0 * PI * k / 48
            PhoneMesh.toScreen(radius * cos(a).toFloat(), radius * sin(a).toFloat(), down, p)
            if (k == 0) path.moveTo(cx + p[0] * scale, cy + p[1] * scale) else path.lineTo(cx + p[0] * scale, cy + p[1] * scale)
        }
        canvas.drawPath(path, ring)
        if (!northKnown) return
        val r = radius * 1.14f
        label(canvas, cardinals[0], 0f, r, down, cx, cy, scale, north)
        label(canvas, cardinals[1], r, 0f, down, cx, cy, scale, cardinal)
        label(canvas, cardinals[2], 0f, -r, down, cx, cy, scale, cardinal)
        label(canvas, cardinals[3], -r, 0f, down, cx, cy, scale, cardinal)
    }

    private fun label(canvas: Canvas, text: String, e: Float, n: Float, u: Float, cx: Float, cy: Float, scale: Float, paint: Paint) {
        PhoneMesh.toScreen(e, n, u, p)
        canvas.drawText(text, cx + p[0] * scale, cy + p[1] * scale + paint.textSize / 3f, paint)
    }

    private fun face(f: Int, m: PhoneMesh, cx: Float, cy: Float, scale: Float) {
        path.rewind()
        val xs = m.screenX[f]
        val ys = m.screenY[f]
        path.moveTo(cx + xs[0] * scale, cy + ys[0] * scale)
        for (k in 1 until m.sides(f)) path.lineTo(cx + xs[k] * scale, cy + ys[k] * scale)
        path.close()
    }

    private fun colourOf(part: PhoneMesh.Part): Int = when (part) {
        PhoneMesh.Part.SCREEN -> screenColour
        PhoneMesh.Part.LENS -> lensColour
        PhoneMesh.Part.FRONT_CAMERA -> frontCameraColour
        PhoneMesh.Part.BODY_SIDE, PhoneMesh.Part.BUMP_SIDE -> darker(bodyColour, 0.8f)
        PhoneMesh.Part.BODY_FRONT -> darker(bodyColour, 0.35f)
        PhoneMesh.Part.BODY_BACK, PhoneMesh.Part.BUMP -> bodyColour
    }

    private fun darker(c: Int, k: Float) = Color.rgb((Color.red(c) * k).toInt(), (Color.green(c) * k).toInt(), (Color.blue(c) * k).toInt())

    private fun shaded(c: Int, shade: Float, alpha: Int): Int {
        val s = shade.coerceIn(0f, 1.2f)
        return Color.argb(
            alpha,
            (Color.red(c) * s).toInt().coerceAtMost(255),
            (Color.green(c) * s).toInt().coerceAtMost(255),
            (Color.blue(c) * s).toInt().coerceAtMost(255),
        )
    }
}
