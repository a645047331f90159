package dev.motionfusion.app.ui

import android.graphics.Bitmap
import android.graphics.Color
import com.google.zxing.BarcodeFormat
import com.google.zxing.EncodeHintType
import com.google.zxing.qrcode.QRCodeWriter
import com.google.zxing.qrcode.decoder.ErrorCorrectionLevel

/**
 * [text] as a QR code (ZXing's encoder, error correction M, the standard 4-module quiet zone, ISO-8859-1 without an
 * ECI header, which some readers mishandle: the command is ASCII), dark modules on white
 * whatever the theme (cameras read dark on light), [pixelsPerModule] pixels a module so that the image scales without
 * blurring the module edges.
 */
internal fun qrBitmap(text: String, pixelsPerModule: Int = 8): Bitmap {
    val hints = mapOf(
        EncodeHintType.ERROR_CORRECTION to ErrorCorrectionLevel.M,
        EncodeHintType.MARGIN to 4,
    )
    // Width and height 0: one matrix cell a module, quiet zone included.
    val matrix = QRCodeWriter().encode(text, BarcodeFormat.QR_CODE, 0, 0, hints)
    val side = matrix.width * pixelsPerModule
    val pixels = IntArray(side * side)
    for (y in 0 until side) for (x in 0 until side) {
        pixels[y * side + x] = if (matrix[x / pixelsPerModule, y / pixelsPerModule]) Color.BLACK else Color.WHITE
    }
    return Bitmap.createBitmap(pixels, side, side, Bitmap.Config.ARGB_8888)
}
